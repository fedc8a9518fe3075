//! Decoded images and the pixel statistics the view tests assert on.

use std::collections::HashMap;
use std::path::Path;

/// An 8-bit RGBA image.
pub struct Image {
    pub width: u32,
    pub height: u32,
    pub rgba: Vec<u8>,
}

impl Image {
    pub fn read(path: &Path) -> Image {
        let file = std::fs::File::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        Self::decode(std::io::BufReader::new(file))
    }

    pub fn decode(reader: impl std::io::Read) -> Image {
        let mut decoder = png::Decoder::new(reader);
        decoder.set_transformations(png::Transformations::EXPAND | png::Transformations::STRIP_16);
        let mut reader = decoder.read_info().expect("a PNG");
        let mut buf = vec![0; reader.output_buffer_size()];
        let info = reader.next_frame(&mut buf).expect("PNG data");
        let pixels = (info.width * info.height) as usize;
        let rgba = match info.color_type {
            png::ColorType::Rgba => buf[..pixels * 4].to_vec(),
            png::ColorType::Rgb => buf[..pixels * 3].chunks(3).flat_map(|c| [c[0], c[1], c[2], 255]).collect(),
            png::ColorType::Grayscale => buf[..pixels].iter().flat_map(|&g| [g, g, g, 255]).collect(),
            png::ColorType::GrayscaleAlpha => {
                buf[..pixels * 2].chunks(2).flat_map(|c| [c[0], c[0], c[0], c[1]]).collect()
            }
            other => panic!("unexpected PNG colour type {other:?}"),
        };
        Image { width: info.width, height: info.height, rgba }
    }

    pub fn pixel(&self, x: u32, y: u32) -> [u8; 3] {
        let i = ((y * self.width + x) * 4) as usize;
        [self.rgba[i], self.rgba[i + 1], self.rgba[i + 2]]
    }

    fn pixels(&self) -> impl Iterator<Item = (u32, u32, [u8; 3])> + '_ {
        (0..self.height).flat_map(move |y| (0..self.width).map(move |x| (x, y, self.pixel(x, y))))
    }

    /// The most frequent colour (the background).
    pub fn background(&self) -> [u8; 3] {
        let mut counts: HashMap<[u8; 3], usize> = HashMap::new();
        for (_, _, p) in self.pixels() {
            *counts.entry(p).or_default() += 1;
        }
        counts.into_iter().max_by_key(|(_, n)| *n).map(|(c, _)| c).unwrap_or([0; 3])
    }

    /// The fraction of pixels that differ from the background.
    pub fn drawn_fraction(&self) -> f64 {
        let bg = self.background();
        let drawn = self.pixels().filter(|(_, _, p)| distance(*p, bg) > 30).count();
        drawn as f64 / (self.width * self.height) as f64
    }

    /// How many distinct colours the image has.
    pub fn colours(&self) -> usize {
        self.pixels().map(|(_, _, p)| p).collect::<std::collections::HashSet<_>>().len()
    }

    /// The fraction of pixels that differ clearly from the same pixel of `other`.
    pub fn changed_fraction(&self, other: &Image) -> f64 {
        assert_eq!((self.width, self.height), (other.width, other.height));
        let changed = self.pixels().zip(other.pixels()).filter(|((_, _, a), (_, _, b))| distance(*a, *b) > 40).count();
        changed as f64 / (self.width * self.height) as f64
    }

    /// How many pixels satisfy `test`, and their mean position.
    pub fn find(&self, test: impl Fn([u8; 3]) -> bool) -> (usize, f64, f64) {
        let (mut n, mut sx, mut sy) = (0usize, 0.0, 0.0);
        for (x, y, p) in self.pixels() {
            if test(p) {
                n += 1;
                sx += x as f64;
                sy += y as f64;
            }
        }
        if n == 0 {
            (0, f64::NAN, f64::NAN)
        } else {
            (n, sx / n as f64, sy / n as f64)
        }
    }
}

fn distance(a: [u8; 3], b: [u8; 3]) -> u32 {
    (0..3).map(|i| (i32::from(a[i]) - i32::from(b[i])).unsigned_abs()).sum()
}

/// Pure magenta [1, 0, 1] under any lighting: red and blue alike and strong,
/// green far below them.
pub fn is_magenta([r, g, b]: [u8; 3]) -> bool {
    let (r, g, b) = (f64::from(r), f64::from(g), f64::from(b));
    r > 90.0 && b > 90.0 && (r - b).abs() < 0.12 * r.max(b) && g < 0.35 * r.min(b)
}

/// The library's default body colour [0.6, 0, 0.5] (purple) under lighting.
pub fn is_purple([r, g, b]: [u8; 3]) -> bool {
    let (r, g, b) = (f64::from(r), f64::from(g), f64::from(b));
    r > 50.0 && b > 40.0 && g < 0.4 * r.min(b) && r > 0.8 * b && b > 0.5 * r
}

/// The world's green y axis [0, 0.6, 0].
pub fn is_green([r, g, b]: [u8; 3]) -> bool {
    let (r, g, b) = (f64::from(r), f64::from(g), f64::from(b));
    g > 60.0 && r < 0.5 * g && b < 0.5 * g
}

/// The world's red x axis [1, 0, 0].
pub fn is_red([r, g, b]: [u8; 3]) -> bool {
    let (r, g, b) = (f64::from(r), f64::from(g), f64::from(b));
    r > 100.0 && g < 0.45 * r && b < 0.45 * r
}
