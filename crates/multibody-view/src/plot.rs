//! Signals against time as PNG or SVG, drawn with plotters. Text uses the
//! DejaVu Sans font shipped in `assets/` (through plotters' `ab_glyph`
//! feature), so no system fonts are needed.

use crate::signals::choose_signals;
use crate::ViewError;
use multibody::Solution;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;
use std::sync::OnceLock;

/// DejaVu Sans 2.37 (Debian's fonts-dejavu-core); license in
/// `assets/DejaVuSans-LICENSE.txt`.
static FONT: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");

/// Lines of one panel take these colours in turn.
pub(crate) const PALETTE: [RGBColor; 8] = [
    RGBColor(31, 95, 191),
    RGBColor(230, 120, 20),
    RGBColor(40, 150, 60),
    RGBColor(200, 40, 40),
    RGBColor(120, 80, 180),
    RGBColor(140, 90, 60),
    RGBColor(20, 160, 170),
    RGBColor(110, 110, 110),
];

/// The file formats of [`write_plot`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PlotFormat {
    Png,
    Svg,
}

impl PlotFormat {
    /// The format a file name asks for (`.png` or `.svg`, any case).
    pub fn from_path(path: &Path) -> Option<Self> {
        match path.extension()?.to_str()?.to_ascii_lowercase().as_str() {
            "png" => Some(PlotFormat::Png),
            "svg" => Some(PlotFormat::Svg),
            _ => None,
        }
    }
}

/// What to plot and how big.
#[derive(Clone, Debug, PartialEq)]
pub struct PlotOptions {
    /// Signal patterns (`*.phi`, `body.r_0[*]`); empty: a guess (joint
    /// coordinates and rates, else free bodies' positions). Signals with
    /// the same unit share a panel.
    pub signals: Vec<String>,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels; 0 for 60 plus 260 per panel.
    pub height: u32,
    /// The most signals plotted (more is an error that says so).
    pub max_signals: usize,
}

impl Default for PlotOptions {
    fn default() -> Self {
        Self { signals: Vec::new(), width: 1000, height: 0, max_signals: 40 }
    }
}

/// What went into a plot.
#[derive(Clone, Debug, PartialEq)]
pub struct PlotSummary {
    pub width: u32,
    pub height: u32,
    /// One panel per unit, each with its signals.
    pub panels: Vec<(String, Vec<String>)>,
}

/// Writes the plot to `path`, as PNG or SVG by its extension, creating its
/// folder if needed.
pub fn write_plot(
    path: impl AsRef<Path>,
    title: &str,
    solution: &Solution,
    options: &PlotOptions,
) -> Result<PlotSummary, ViewError> {
    write_image(path.as_ref(), || plot_png(title, solution, options), || plot_svg(title, solution, options))
}

/// Writes an image to `path`, drawn as PNG or SVG by its extension,
/// creating its folder if needed.
pub(crate) fn write_image<S>(
    path: &Path,
    png: impl FnOnce() -> Result<(Vec<u8>, S), ViewError>,
    svg: impl FnOnce() -> Result<(String, S), ViewError>,
) -> Result<S, ViewError> {
    let format = PlotFormat::from_path(path).ok_or_else(|| ViewError::Format { path: path.to_path_buf() })?;
    let (bytes, summary) = match format {
        PlotFormat::Png => png()?,
        PlotFormat::Svg => {
            let (text, summary) = svg()?;
            (text.into_bytes(), summary)
        }
    };
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| ViewError::io(dir, e))?;
    }
    std::fs::write(path, bytes).map_err(|e| ViewError::io(path, e))?;
    Ok(summary)
}

/// The plot as PNG bytes.
pub fn plot_png(title: &str, solution: &Solution, options: &PlotOptions) -> Result<(Vec<u8>, PlotSummary), ViewError> {
    let layout = Layout::new(solution, options)?;
    let (w, h) = (layout.summary.width, layout.summary.height);
    let mut rgb = vec![255u8; w as usize * h as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, (w, h)).into_drawing_area();
        draw(&root, title, solution, &layout)?;
        root.present().map_err(plot_error)?;
    }
    Ok((encode_png(&rgb, w, h)?, layout.summary))
}

/// RGB pixels as PNG bytes.
pub(crate) fn encode_png(rgb: &[u8], w: u32, h: u32) -> Result<Vec<u8>, ViewError> {
    let mut png_bytes = Vec::new();
    let mut encoder = png::Encoder::new(&mut png_bytes, w, h);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    let mut writer = encoder.write_header().map_err(|e| ViewError::Plot(e.to_string()))?;
    writer.write_image_data(rgb).map_err(|e| ViewError::Plot(e.to_string()))?;
    drop(writer);
    Ok(png_bytes)
}

/// The plot as SVG text.
pub fn plot_svg(title: &str, solution: &Solution, options: &PlotOptions) -> Result<(String, PlotSummary), ViewError> {
    let layout = Layout::new(solution, options)?;
    let mut text = String::new();
    {
        let root =
            SVGBackend::with_string(&mut text, (layout.summary.width, layout.summary.height)).into_drawing_area();
        draw(&root, title, solution, &layout)?;
        root.present().map_err(plot_error)?;
    }
    Ok((text, layout.summary))
}

struct Layout {
    summary: PlotSummary,
}

impl Layout {
    fn new(solution: &Solution, options: &PlotOptions) -> Result<Self, ViewError> {
        if solution.is_empty() {
            return Err(ViewError::EmptySolution);
        }
        let signals = choose_signals(solution, &options.signals)?;
        if signals.is_empty() {
            return Err(ViewError::NothingToPlot);
        }
        if signals.len() > options.max_signals {
            return Err(ViewError::Plot(format!(
                "{} signals match; a plot shows at most {}: choose fewer (e.g. `*.phi`)",
                signals.len(),
                options.max_signals
            )));
        }
        let mut panels: Vec<(String, Vec<String>)> = Vec::new();
        for s in signals {
            let unit = solution.unit(&s).unwrap_or("").to_string();
            match panels.iter_mut().find(|(u, _)| *u == unit) {
                Some((_, list)) => list.push(s),
                None => panels.push((unit, vec![s])),
            }
        }
        let width = options.width.max(200);
        let height = if options.height > 0 { options.height.max(120) } else { 60 + 260 * panels.len() as u32 };
        Ok(Self { summary: PlotSummary { width, height, panels } })
    }
}

pub(crate) fn plot_error<E: std::error::Error + Send + Sync>(e: DrawingAreaErrorKind<E>) -> ViewError {
    ViewError::Plot(e.to_string())
}

pub(crate) fn register_font() -> Result<(), ViewError> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok = *REGISTERED.get_or_init(|| {
        [FontStyle::Normal, FontStyle::Bold]
            .into_iter()
            .all(|style| plotters::style::register_font("sans-serif", style, FONT).is_ok())
    });
    if ok {
        Ok(())
    } else {
        Err(ViewError::Plot("the shipped font could not be read".into()))
    }
}

/// Runs of (time, value) points without gaps.
type Segments = Vec<Vec<(f64, f64)>>;

/// Time and value pairs of a signal, split where it is not finite, and
/// thinned to the lowest and highest value per pixel column.
fn segments(time: &[f64], values: &[f64], columns: usize) -> Segments {
    let n = time.len().min(values.len());
    let per_bucket = n.div_ceil(columns.max(1)).max(1);
    let mut out: Vec<Vec<(f64, f64)>> = Vec::new();
    let mut current: Vec<(f64, f64)> = Vec::new();
    let mut k = 0;
    while k < n {
        let end = (k + per_bucket).min(n);
        if per_bucket <= 2 {
            for i in k..end {
                if values[i].is_finite() && time[i].is_finite() {
                    current.push((time[i], values[i]));
                } else if !current.is_empty() {
                    out.push(std::mem::take(&mut current));
                }
            }
        } else {
            let (mut lo, mut hi) = (None::<usize>, None::<usize>);
            let mut broken = false;
            for i in k..end {
                if !values[i].is_finite() {
                    broken = true;
                    continue;
                }
                if lo.is_none_or(|j| values[i] < values[j]) {
                    lo = Some(i);
                }
                if hi.is_none_or(|j| values[i] > values[j]) {
                    hi = Some(i);
                }
            }
            if let (Some(a), Some(b)) = (lo, hi) {
                let (a, b) = if a <= b { (a, b) } else { (b, a) };
                current.push((time[a], values[a]));
                if b != a {
                    current.push((time[b], values[b]));
                }
            }
            if broken && !current.is_empty() {
                out.push(std::mem::take(&mut current));
            }
        }
        k = end;
    }
    if !current.is_empty() {
        out.push(current);
    }
    out
}

/// The value axis: the data with a margin; a flat signal (constant, or
/// rounding noise about a constant) gets a band around its value, so that
/// its axis reads e.g. -1 .. 1 rather than magnifying the noise.
fn nice_range(lo: f64, hi: f64) -> (f64, f64) {
    if !lo.is_finite() || !hi.is_finite() {
        return (-1.0, 1.0);
    }
    let scale = hi.abs().max(lo.abs());
    if hi - lo <= 1e-9 * scale.max(1.0) {
        let mid = 0.5 * (lo + hi);
        let d = if scale < 1e-9 { 1.0 } else { 0.1 * scale };
        return (mid - d, mid + d);
    }
    let pad = 0.05 * (hi - lo);
    (lo - pad, hi + pad)
}

/// Enough decimals to tell apart the ticks of an axis spanning `lo .. hi`.
fn tick_decimals(lo: f64, hi: f64) -> usize {
    let step = (hi - lo) / 10.0;
    (-step.log10().floor()).clamp(0.0, 12.0) as usize
}

fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
    solution: &Solution,
    layout: &Layout,
) -> Result<(), ViewError>
where
    DB::ErrorType: 'static,
{
    register_font()?;
    root.fill(&WHITE).map_err(plot_error)?;
    let body = root.titled(title, ("sans-serif", 22).into_font().color(&BLACK)).map_err(plot_error)?;
    let time = solution.time();
    let (t0, t1) = (time[0], time[time.len() - 1]);
    let (t0, t1) = if t1 > t0 { (t0, t1) } else { (t0, t0 + 1.0) };
    let panels = &layout.summary.panels;
    let areas = body.split_evenly((panels.len(), 1));
    let columns = layout.summary.width as usize;
    for ((unit, names), area) in panels.iter().zip(areas.iter()) {
        let series: Vec<(&String, Segments)> =
            names.iter().map(|n| (n, segments(time, solution.get(n).unwrap_or(&[]), columns))).collect();
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for (_, segs) in &series {
            for &(_, v) in segs.iter().flatten() {
                lo = lo.min(v);
                hi = hi.max(v);
            }
        }
        let (lo, hi) = nice_range(lo, hi);
        let decimals = tick_decimals(lo, hi);
        let mut chart = ChartBuilder::on(area)
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(78)
            .build_cartesian_2d(t0..t1, lo..hi)
            .map_err(plot_error)?;
        let unit_label = if unit.is_empty() { "[1]".to_string() } else { format!("[{unit}]") };
        chart
            .configure_mesh()
            .x_desc("time [s]")
            .y_desc(unit_label)
            .y_label_formatter(&|v| format!("{v:.decimals$}"))
            .label_style(("sans-serif", 14))
            .axis_desc_style(("sans-serif", 15))
            .light_line_style(RGBColor(238, 240, 243))
            .bold_line_style(RGBColor(215, 219, 224))
            .draw()
            .map_err(plot_error)?;
        for (i, (name, segs)) in series.iter().enumerate() {
            let color = PALETTE[i % PALETTE.len()];
            for (k, seg) in segs.iter().enumerate() {
                let drawn = chart
                    .draw_series(LineSeries::new(seg.iter().copied(), color.stroke_width(2)))
                    .map_err(plot_error)?;
                if k == 0 {
                    drawn
                        .label(name.as_str())
                        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2)));
                }
            }
        }
        chart
            .configure_series_labels()
            .label_font(("sans-serif", 14))
            .background_style(WHITE.mix(0.85))
            .border_style(RGBColor(180, 185, 190))
            .position(SeriesLabelPosition::UpperRight)
            .draw()
            .map_err(plot_error)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thinning_keeps_extremes_and_splits_at_nan() {
        let time: Vec<f64> = (0..1000).map(|k| k as f64).collect();
        let mut values: Vec<f64> = time.iter().map(|t| (t / 50.0).sin()).collect();
        values[500] = f64::NAN;
        let segs = segments(&time, &values, 100);
        assert_eq!(segs.len(), 2);
        let all: Vec<f64> = segs.iter().flatten().map(|p| p.1).collect();
        let max = all.iter().cloned().fold(f64::MIN, f64::max);
        assert!((max - 1.0).abs() < 1e-3, "{max}");
        assert!(segs.iter().map(Vec::len).sum::<usize>() <= 200);
    }

    #[test]
    fn format_from_extension() {
        assert_eq!(PlotFormat::from_path(Path::new("a/b.PNG")), Some(PlotFormat::Png));
        assert_eq!(PlotFormat::from_path(Path::new("b.svg")), Some(PlotFormat::Svg));
        assert_eq!(PlotFormat::from_path(Path::new("b.pdf")), None);
    }
}
