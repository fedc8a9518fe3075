//! Views of a linear model ([`Linearization`]): its matrices, operating
//! point and poles as JSON, a damping table for the terminal (the columns
//! of Dyad's DampReport), and a Bode plot (PNG or SVG, drawn with plotters
//! like the signal plots).

use crate::json::Json;
use crate::plot::{encode_png, plot_error, register_font, write_image, PALETTE};
use crate::ViewError;
use multibody::{Linearization, Pole};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::fmt::Write;
use std::path::Path;

/// The linear model as one JSON object:
///
/// - `time`: the operating point's time;
/// - `state_names`, `input_names`, `output_names`: the names of A's
///   coordinates, of B's and D's columns, of C's and D's rows;
/// - `A`, `B`, `C`, `D`: lists of rows (an empty matrix, one with no rows
///   or no columns, as `[]`);
/// - `operating_point`: `state` (the simulator's whole state vector, a
///   list: its entries are not the coordinates of A), `inputs` and
///   `outputs` (objects name -> value);
/// - `rates`: object coordinate name -> its rate at the operating point
///   (zero at an equilibrium);
/// - `exact` (boolean), `accuracy` (number or `null`), `notes` (strings);
/// - `poles`: a list of `{ "re", "im", "damping_ratio", "frequency_rad_s",
///   "frequency_hz", "time_constant_s" }`, slowest first.
///
/// Numbers are written exactly (shortest round-trip form); numbers that are
/// not finite (the infinite time constant of a pole on the imaginary axis)
/// as `null`.
pub fn linearization_json(lin: &Linearization) -> String {
    let mut j = Json::new();
    j.begin_object();
    j.key("time").number(lin.time);
    j.key("state_names");
    strings(&mut j, &lin.state_names);
    j.key("input_names");
    strings(&mut j, &lin.input_names);
    j.key("output_names");
    strings(&mut j, &lin.output_names);
    for (key, m) in [("A", &lin.a), ("B", &lin.b), ("C", &lin.c), ("D", &lin.d)] {
        j.key(key).begin_array();
        if !m.is_empty() {
            for r in 0..m.nrows() {
                j.begin_array();
                for c in 0..m.ncols() {
                    j.number(m[(r, c)]);
                }
                j.end_array();
            }
        }
        j.end_array();
    }
    j.key("operating_point").begin_object();
    j.key("state").numbers(&lin.state);
    j.key("inputs");
    named(&mut j, &lin.input_names, &lin.input_values);
    j.key("outputs");
    named(&mut j, &lin.output_names, &lin.output_values);
    j.end_object();
    j.key("rates");
    named(&mut j, &lin.state_names, &lin.rates);
    j.key("exact").boolean(lin.exact);
    // `number` writes what is not finite as null.
    j.key("accuracy").number(lin.accuracy.unwrap_or(f64::NAN));
    j.key("notes");
    strings(&mut j, &lin.notes);
    j.key("poles").begin_array();
    for p in lin.poles() {
        j.begin_object();
        j.key("re").number(p.re);
        j.key("im").number(p.im);
        j.key("damping_ratio").number(p.damping_ratio);
        j.key("frequency_rad_s").number(p.frequency);
        j.key("frequency_hz").number(p.frequency / std::f64::consts::TAU);
        j.key("time_constant_s").number(p.time_constant);
        j.end_object();
    }
    j.end_array();
    j.end_object();
    j.finish()
}

fn strings(j: &mut Json, list: &[String]) {
    j.begin_array();
    for s in list {
        j.string(s);
    }
    j.end_array();
}

fn named(j: &mut Json, names: &[String], values: &[f64]) {
    j.begin_object();
    for (name, &v) in names.iter().zip(values) {
        j.key(name).number(v);
    }
    j.end_object();
}

/// The poles as a plain-text table with the columns of Dyad's DampReport:
/// Pole, DampingRatio, Frequency [rad/s], Frequency [Hz], TimeConstant [s];
/// one row per real pole and per conjugate pair (`a ± bi`), slowest first.
pub fn damping_report(lin: &Linearization) -> String {
    let header = ["Pole", "DampingRatio", "Frequency [rad/s]", "Frequency [Hz]", "TimeConstant [s]"];
    let poles = lin.poles();
    let mut rows: Vec<[String; 5]> = Vec::new();
    let mut k = 0;
    while k < poles.len() {
        let p = poles[k];
        let pair = poles.get(k + 1).filter(|q| p.im != 0.0 && conjugates(&p, q));
        let pole = if pair.is_some() {
            format!("{} ± {}i", general(p.re), general(p.im.abs()))
        } else if p.im != 0.0 {
            format!("{} {} {}i", general(p.re), if p.im < 0.0 { '-' } else { '+' }, general(p.im.abs()))
        } else {
            general(p.re)
        };
        rows.push([
            pole,
            general(p.damping_ratio),
            general(p.frequency),
            general(p.frequency / std::f64::consts::TAU),
            general(p.time_constant),
        ]);
        k += if pair.is_some() { 2 } else { 1 };
    }
    let mut widths = header.map(|h| h.chars().count());
    for row in &rows {
        for (w, cell) in widths.iter_mut().zip(row) {
            *w = (*w).max(cell.chars().count());
        }
    }
    let mut out = String::new();
    let mut line = |cells: &[&str]| {
        let text: Vec<String> = cells.iter().zip(widths).map(|(c, w)| format!("{c:>w$}")).collect();
        let _ = writeln!(out, "{}", text.join("  ").trim_end());
    };
    line(&header);
    let rule: Vec<String> = widths.iter().map(|&w| "-".repeat(w)).collect();
    line(&rule.iter().map(String::as_str).collect::<Vec<_>>());
    for row in &rows {
        line(&row.iter().map(String::as_str).collect::<Vec<_>>());
    }
    if rows.is_empty() {
        out.push_str("(the model has no states, so no poles)\n");
    }
    out
}

/// Whether `q` is the complex conjugate of `p` (up to rounding).
fn conjugates(p: &Pole, q: &Pole) -> bool {
    let tol = 1e-9 * p.frequency.max(1e-300);
    (p.re - q.re).abs() <= tol && (p.im + q.im).abs() <= tol
}

/// A number with six significant digits, without trailing zeros (like C's
/// `%g`).
fn general(x: f64) -> String {
    if x.is_nan() {
        return "NaN".into();
    }
    if x.is_infinite() {
        return if x > 0.0 { "inf" } else { "-inf" }.into();
    }
    if x == 0.0 {
        return "0".into();
    }
    let exponent = x.abs().log10().floor() as i32;
    if (-4..6).contains(&exponent) {
        let decimals = (5 - exponent).max(0) as usize;
        let s = format!("{x:.decimals$}");
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    } else {
        let s = format!("{x:.5e}");
        match s.split_once('e') {
            Some((mantissa, e)) if mantissa.contains('.') => {
                format!("{}e{e}", mantissa.trim_end_matches('0').trim_end_matches('.'))
            }
            _ => s,
        }
    }
}

/// What a Bode plot shows and how big.
#[derive(Clone, Debug, PartialEq)]
pub struct BodeOptions {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels (both panels and the title).
    pub height: u32,
    /// Frequencies sampled, spaced evenly on the logarithmic axis.
    pub points: usize,
    /// The frequency range in rad/s; `None`: from the poles (see
    /// [`default_frequency_range`]).
    pub range: Option<(f64, f64)>,
    /// The (input, output) pairs drawn; `None`: every pair.
    pub pairs: Option<Vec<(String, String)>>,
}

impl Default for BodeOptions {
    fn default() -> Self {
        Self { width: 1000, height: 800, points: 400, range: None, pairs: None }
    }
}

/// What went into a Bode plot.
#[derive(Clone, Debug, PartialEq)]
pub struct BodeSummary {
    pub width: u32,
    pub height: u32,
    /// The frequency range in rad/s.
    pub range: (f64, f64),
    pub points: usize,
    /// The (input, output) pairs drawn, in the legend's order.
    pub pairs: Vec<(String, String)>,
}

/// The frequency response of one input-output pair.
#[derive(Clone, Debug, PartialEq)]
pub struct BodeCurve {
    pub input: String,
    pub output: String,
    /// `20 log10 |G(jw)|` at each frequency (`-inf` where the gain is zero,
    /// NaN where `jw` is a pole).
    pub magnitude_db: Vec<f64>,
    /// The phase of `G(jw)` in degrees, unwrapped along frequency (each
    /// value the one nearest the previous; the first in (-180, 180]); NaN
    /// where it is undefined.
    pub phase_deg: Vec<f64>,
}

/// The sampled frequency responses a Bode plot draws.
#[derive(Clone, Debug, PartialEq)]
pub struct BodeResponse {
    /// Frequencies in rad/s, spaced evenly on a logarithmic axis.
    pub frequencies: Vec<f64>,
    pub curves: Vec<BodeCurve>,
}

/// The frequency range a Bode plot shows by default, in rad/s: a decade
/// below the slowest pole that is not at zero to a decade above the
/// fastest; 0.01 .. 100 without such poles. Poles within 1e-6 (relative to
/// the fastest) of zero count as zero: differences put the double pole of
/// a free coordinate there.
pub fn default_frequency_range(lin: &Linearization) -> (f64, f64) {
    let poles = lin.poles();
    let fastest = poles.iter().map(|p| p.frequency).filter(|f| f.is_finite()).fold(0.0, f64::max);
    let nonzero: Vec<f64> =
        poles.iter().map(|p| p.frequency).filter(|&f| f.is_finite() && f > 1e-6 * fastest && f > 0.0).collect();
    if nonzero.is_empty() {
        return (0.01, 100.0);
    }
    let lo = nonzero.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = nonzero.iter().copied().fold(0.0, f64::max);
    (lo / 10.0, hi * 10.0)
}

/// The frequency responses a Bode plot with these options draws, from
/// [`Linearization::frequency_response`].
pub fn bode_response(lin: &Linearization, options: &BodeOptions) -> Result<BodeResponse, ViewError> {
    let pairs = chosen_pairs(lin, options)?;
    let (lo, hi) = frequency_range(lin, options)?;
    let n = options.points.max(2);
    let (l0, l1) = (lo.log10(), hi.log10());
    let frequencies: Vec<f64> = (0..n)
        .map(|k| match k {
            0 => lo,
            k if k == n - 1 => hi,
            k => 10f64.powf(l0 + (l1 - l0) * k as f64 / (n - 1) as f64),
        })
        .collect();
    let curves = pairs
        .into_iter()
        .map(|(i, o)| {
            let g = if lin.a.nrows() == 0 {
                // No states: G = D. (The engine's LU solve panics on a 0x0 matrix.)
                vec![(lin.d[(o, i)], 0.0); frequencies.len()]
            } else {
                lin.frequency_response(i, o, &frequencies)
            };
            let magnitude_db = g.iter().map(|&(re, im)| 20.0 * re.hypot(im).log10()).collect();
            let mut phase_deg: Vec<f64> = g
                .iter()
                .map(|&(re, im)| if re == 0.0 && im == 0.0 { f64::NAN } else { im.atan2(re).to_degrees() })
                .collect();
            unwrap_degrees(&mut phase_deg);
            BodeCurve {
                input: lin.input_names[i].clone(),
                output: lin.output_names[o].clone(),
                magnitude_db,
                phase_deg,
            }
        })
        .collect();
    Ok(BodeResponse { frequencies, curves })
}

/// Makes a phase continuous: each finite value is moved by whole turns to
/// the one nearest the previous finite value.
fn unwrap_degrees(phase: &mut [f64]) {
    let mut previous: Option<f64> = None;
    for p in phase.iter_mut().filter(|p| p.is_finite()) {
        if let Some(q) = previous {
            *p += 360.0 * ((q - *p) / 360.0).round();
        }
        previous = Some(*p);
    }
}

/// The most curves one Bode plot draws.
const MAX_CURVES: usize = 40;

/// The (input, output) index pairs to draw.
fn chosen_pairs(lin: &Linearization, options: &BodeOptions) -> Result<Vec<(usize, usize)>, ViewError> {
    let (no_inputs, no_outputs) = (lin.input_names.is_empty(), lin.output_names.is_empty());
    if no_inputs || no_outputs {
        let what = match (no_inputs, no_outputs) {
            (true, true) => "no inputs and no outputs",
            (true, false) => "no inputs",
            _ => "no outputs",
        };
        return Err(ViewError::Plot(format!(
            "the linear model has {what}, so there is no frequency response to draw: \
             choose its inputs with --inputs (top-level RealInputs) and its outputs with --outputs \
             (outputs or any variable)"
        )));
    }
    let pairs: Vec<(usize, usize)> = match &options.pairs {
        None => (0..lin.input_names.len()).flat_map(|i| (0..lin.output_names.len()).map(move |o| (i, o))).collect(),
        Some(named) => {
            let mut pairs = Vec::with_capacity(named.len());
            for (input, output) in named {
                let i = find(&lin.input_names, input, "input")?;
                let o = find(&lin.output_names, output, "output")?;
                pairs.push((i, o));
            }
            pairs
        }
    };
    if pairs.is_empty() {
        return Err(ViewError::Plot("no input-output pairs to draw: the list of pairs is empty".into()));
    }
    if pairs.len() > MAX_CURVES {
        return Err(ViewError::Plot(format!(
            "{} input-output pairs; a Bode plot shows at most {MAX_CURVES}: choose fewer inputs, outputs or pairs",
            pairs.len()
        )));
    }
    Ok(pairs)
}

fn find(names: &[String], name: &str, what: &str) -> Result<usize, ViewError> {
    names.iter().position(|n| n == name).ok_or_else(|| {
        ViewError::Plot(format!(
            "`{name}` is not an {what} of the linear model (its {what}s: {}; choose them with --{what}s)",
            names.join(", ")
        ))
    })
}

fn frequency_range(lin: &Linearization, options: &BodeOptions) -> Result<(f64, f64), ViewError> {
    match options.range {
        None => Ok(default_frequency_range(lin)),
        Some((lo, hi)) if lo.is_finite() && hi.is_finite() && 0.0 < lo && lo < hi => Ok((lo, hi)),
        Some((lo, hi)) => Err(ViewError::Plot(format!(
            "the frequency range {lo} .. {hi} rad/s is not one a logarithmic axis can show: \
             it needs 0 < low < high"
        ))),
    }
}

/// Writes the Bode plot to `path`, as PNG or SVG by its extension,
/// creating its folder if needed.
pub fn write_bode(
    path: impl AsRef<Path>,
    title: &str,
    lin: &Linearization,
    options: &BodeOptions,
) -> Result<BodeSummary, ViewError> {
    write_image(path.as_ref(), || bode_png(title, lin, options), || bode_svg(title, lin, options))
}

/// The Bode plot as PNG bytes.
pub fn bode_png(title: &str, lin: &Linearization, options: &BodeOptions) -> Result<(Vec<u8>, BodeSummary), ViewError> {
    let (response, summary) = prepare(lin, options)?;
    let (w, h) = (summary.width, summary.height);
    let mut rgb = vec![255u8; w as usize * h as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, (w, h)).into_drawing_area();
        draw(&root, title, &response)?;
        root.present().map_err(plot_error)?;
    }
    Ok((encode_png(&rgb, w, h)?, summary))
}

/// The Bode plot as SVG text.
pub fn bode_svg(title: &str, lin: &Linearization, options: &BodeOptions) -> Result<(String, BodeSummary), ViewError> {
    let (response, summary) = prepare(lin, options)?;
    let mut text = String::new();
    {
        let root = SVGBackend::with_string(&mut text, (summary.width, summary.height)).into_drawing_area();
        draw(&root, title, &response)?;
        root.present().map_err(plot_error)?;
    }
    Ok((text, summary))
}

fn prepare(lin: &Linearization, options: &BodeOptions) -> Result<(BodeResponse, BodeSummary), ViewError> {
    let response = bode_response(lin, options)?;
    let f = &response.frequencies;
    let summary = BodeSummary {
        width: options.width.max(200),
        height: options.height.max(240),
        range: (f[0], f[f.len() - 1]),
        points: f.len(),
        pairs: response.curves.iter().map(|c| (c.input.clone(), c.output.clone())).collect(),
    };
    Ok((response, summary))
}

/// The widest span of the magnitude axis: deeper values (a gain that is
/// zero but for rounding) leave the panel instead of squashing the rest.
const MAX_DB_SPAN: f64 = 200.0;

/// The magnitude axis in dB: the data with a margin, at most
/// [`MAX_DB_SPAN`] deep; a flat curve gets a band of 10 dB either side.
fn magnitude_axis(curves: &[BodeCurve]) -> (f64, f64) {
    let (lo, hi) = finite_bounds(curves.iter().flat_map(|c| &c.magnitude_db));
    if !lo.is_finite() {
        return (-10.0, 10.0);
    }
    let lo = lo.max(hi - MAX_DB_SPAN);
    if hi - lo < 1e-6 * hi.abs().max(1.0) {
        return (lo - 10.0, hi + 10.0);
    }
    let pad = 0.05 * (hi - lo);
    (lo - pad, hi + pad)
}

/// The phase axis in degrees: the data widened to multiples of 45.
fn phase_axis(curves: &[BodeCurve]) -> (f64, f64) {
    let (lo, hi) = finite_bounds(curves.iter().flat_map(|c| &c.phase_deg));
    if !lo.is_finite() {
        return (-180.0, 180.0);
    }
    let (mut lo, mut hi) = ((lo / 45.0 - 1e-9).floor() * 45.0, (hi / 45.0 + 1e-9).ceil() * 45.0);
    if hi - lo < 90.0 {
        lo -= 45.0;
        hi += 45.0;
    }
    (lo, hi)
}

fn finite_bounds<'a>(values: impl Iterator<Item = &'a f64>) -> (f64, f64) {
    values.filter(|v| v.is_finite()).fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| (lo.min(v), hi.max(v)))
}

/// Runs of (frequency, value) points inside `lo ..= hi`, split where a value
/// is not finite or leaves the axis.
fn runs(frequencies: &[f64], values: &[f64], (lo, hi): (f64, f64)) -> Vec<Vec<(f64, f64)>> {
    let mut out = Vec::new();
    let mut current = Vec::new();
    for (&w, &v) in frequencies.iter().zip(values) {
        if v.is_finite() && (lo..=hi).contains(&v) {
            current.push((w, v));
        } else if !current.is_empty() {
            out.push(std::mem::take(&mut current));
        }
    }
    if !current.is_empty() {
        out.push(current);
    }
    out
}

/// A frequency as a tick label: 0.01, 0.5, 1, 20, 1e+06.
fn frequency_label(w: f64) -> String {
    if (1e-4..1e5).contains(&w) {
        general(w)
    } else {
        format!("{w:.0e}")
    }
}

/// Which values of a curve a panel draws.
type Values = fn(&BodeCurve) -> &[f64];

fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
    response: &BodeResponse,
) -> Result<(), ViewError>
where
    DB::ErrorType: 'static,
{
    register_font()?;
    root.fill(&WHITE).map_err(plot_error)?;
    let body = root.titled(title, ("sans-serif", 22).into_font().color(&BLACK)).map_err(plot_error)?;
    let areas = body.split_evenly((2, 1));
    let f = &response.frequencies;
    let (w0, w1) = (f[0], f[f.len() - 1]);
    let panels: [(&str, (f64, f64), Values); 2] = [
        ("magnitude [dB]", magnitude_axis(&response.curves), |c| &c.magnitude_db),
        ("phase [deg]", phase_axis(&response.curves), |c| &c.phase_deg),
    ];
    for (k, ((label, (lo, hi), values), area)) in panels.into_iter().zip(areas.iter()).enumerate() {
        let mut chart = ChartBuilder::on(area)
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(70)
            .build_cartesian_2d((w0..w1).log_scale(), lo..hi)
            .map_err(plot_error)?;
        let decimals = if hi - lo >= 10.0 { 0 } else { 2 };
        chart
            .configure_mesh()
            .x_desc("frequency [rad/s]")
            .y_desc(label)
            .x_label_formatter(&|w| frequency_label(*w))
            .y_label_formatter(&|v| format!("{v:.decimals$}"))
            .label_style(("sans-serif", 14))
            .axis_desc_style(("sans-serif", 15))
            .light_line_style(RGBColor(238, 240, 243))
            .bold_line_style(RGBColor(215, 219, 224))
            .draw()
            .map_err(plot_error)?;
        for (i, curve) in response.curves.iter().enumerate() {
            let color = PALETTE[i % PALETTE.len()];
            let mut runs = runs(f, values(curve), (lo, hi));
            if runs.is_empty() {
                // Nothing to draw (a gain of zero): the legend still names it.
                runs.push(Vec::new());
            }
            let mut labelled = false;
            for run in runs {
                let drawn = chart.draw_series(LineSeries::new(run, color.stroke_width(2))).map_err(plot_error)?;
                // The legend is in the magnitude panel; the phase panel's
                // curves take the same colours.
                if k == 0 && !labelled {
                    labelled = true;
                    drawn
                        .label(format!("{} -> {}", curve.input, curve.output))
                        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2)));
                }
            }
        }
        if k == 0 {
            chart
                .configure_series_labels()
                .label_font(("sans-serif", 14))
                .background_style(WHITE.mix(0.85))
                .border_style(RGBColor(180, 185, 190))
                .position(SeriesLabelPosition::UpperRight)
                .draw()
                .map_err(plot_error)?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::DMatrix;
    use serde_json::Value;

    /// A linear model with these matrices (rows) and names; the operating
    /// point is made up.
    fn model(
        a: &[&[f64]],
        b: &[&[f64]],
        c: &[&[f64]],
        d: &[&[f64]],
        inputs: &[&str],
        outputs: &[&str],
    ) -> Linearization {
        let n = a.len();
        let (m, p) = (inputs.len(), outputs.len());
        let matrix = |rows: &[&[f64]], nr: usize, nc: usize| {
            assert_eq!(rows.len(), nr);
            DMatrix::from_fn(nr, nc, |r, c| rows[r][c])
        };
        let names = |list: &[&str]| list.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        Linearization {
            a: matrix(a, n, n),
            b: matrix(b, n, m),
            c: matrix(c, p, n),
            d: matrix(d, p, m),
            state_names: (1..=n).map(|k| format!("x{k}")).collect(),
            input_names: names(inputs),
            output_names: names(outputs),
            time: 1.5,
            state: vec![0.25; n + 1],
            input_values: (0..m).map(|k| k as f64 + 0.5).collect(),
            output_values: (0..p).map(|k| -(k as f64) - 0.125).collect(),
            rates: vec![0.0; n],
            exact: false,
            accuracy: None,
            notes: vec!["made by hand \"for tests\"".into()],
        }
    }

    /// `y'' + 2 zeta w y' + w^2 y = u`, output y: G(s) = 1 / (s^2 + 2 zeta w s + w^2).
    fn oscillator(w: f64, zeta: f64) -> Linearization {
        model(&[&[0.0, 1.0], &[-w * w, -2.0 * zeta * w]], &[&[0.0], &[1.0]], &[&[1.0, 0.0]], &[&[0.0]], &["u"], &["y"])
    }

    fn numbers(v: &Value) -> Vec<f64> {
        v.as_array().unwrap_or_else(|| panic!("not a list: {v}")).iter().map(|x| x.as_f64().unwrap()).collect()
    }

    fn rows(v: &Value) -> Vec<Vec<f64>> {
        v.as_array().unwrap_or_else(|| panic!("not a list: {v}")).iter().map(numbers).collect()
    }

    /// An object's entries in the order written (serde_json keeps them sorted,
    /// which is the written order in these tests).
    fn object(v: &Value) -> Vec<(String, f64)> {
        let map = v.as_object().unwrap_or_else(|| panic!("not an object: {v}"));
        map.iter().map(|(k, x)| (k.clone(), x.as_f64().unwrap())).collect()
    }

    fn rel(a: f64, b: f64) -> f64 {
        (a - b).abs() / b.abs()
    }

    #[test]
    fn json_has_the_matrices_point_and_poles() {
        let (w, zeta) = (2.0, 0.2);
        let mut lin = oscillator(w, zeta);
        lin.accuracy = Some(3e-11);
        lin.exact = true;
        let text = linearization_json(&lin);
        let v: Value = serde_json::from_str(&text).expect("valid JSON");
        assert_eq!(v["time"], 1.5);
        assert_eq!(v["state_names"], serde_json::json!(["x1", "x2"]));
        assert_eq!(v["input_names"], serde_json::json!(["u"]));
        assert_eq!(v["output_names"], serde_json::json!(["y"]));
        assert_eq!(rows(&v["A"]), [[0.0, 1.0], [-4.0, -0.8]]);
        assert_eq!(rows(&v["B"]), [[0.0], [1.0]]);
        assert_eq!(rows(&v["C"]), [[1.0, 0.0]]);
        assert_eq!(rows(&v["D"]), [[0.0]]);
        assert_eq!(numbers(&v["operating_point"]["state"]), [0.25, 0.25, 0.25]);
        assert_eq!(object(&v["operating_point"]["inputs"]), [("u".to_string(), 0.5)]);
        assert_eq!(object(&v["operating_point"]["outputs"]), [("y".to_string(), -0.125)]);
        assert_eq!(object(&v["rates"]), [("x1".to_string(), 0.0), ("x2".to_string(), 0.0)]);
        assert_eq!(v["exact"], true);
        assert_eq!(v["accuracy"], 3e-11);
        assert_eq!(v["notes"], serde_json::json!(["made by hand \"for tests\""]));
        let poles = v["poles"].as_array().unwrap();
        assert_eq!(poles.len(), 2);
        let wd = w * (1.0 - zeta * zeta).sqrt();
        for (p, im) in poles.iter().zip([-wd, wd]) {
            let num = |k: &str| p[k].as_f64().unwrap_or_else(|| panic!("{k} in {p}"));
            assert!((num("re") + zeta * w).abs() < 1e-12, "{p}");
            assert!((num("im") - im).abs() < 1e-12, "{p}");
            assert!((num("damping_ratio") - zeta).abs() < 1e-12, "{p}");
            assert!((num("frequency_rad_s") - w).abs() < 1e-12, "{p}");
            assert!((num("frequency_hz") - w / std::f64::consts::TAU).abs() < 1e-12, "{p}");
            assert!((num("time_constant_s") - 1.0 / (zeta * w)).abs() < 1e-12, "{p}");
            assert_eq!(p.as_object().unwrap().len(), 6);
        }
        // Exactly the keys other code reads.
        let keys: Vec<&str> = v.as_object().unwrap().keys().map(String::as_str).collect();
        let mut expected = vec![
            "time",
            "state_names",
            "input_names",
            "output_names",
            "A",
            "B",
            "C",
            "D",
            "operating_point",
            "rates",
            "exact",
            "accuracy",
            "notes",
            "poles",
        ];
        let mut sorted = keys.clone();
        sorted.sort();
        expected.sort();
        assert_eq!(sorted, expected);
    }

    #[test]
    fn json_writes_empty_matrices_and_infinite_time_constants_as_null() {
        // Undamped, with no inputs and no outputs: B, C, D are empty.
        let lin = model(&[&[0.0, 1.0], &[-9.0, 0.0]], &[&[], &[]], &[], &[], &[], &[]);
        let v: Value = serde_json::from_str(&linearization_json(&lin)).expect("valid JSON");
        for key in ["B", "C", "D"] {
            assert_eq!(v[key], serde_json::json!([]), "{key}");
        }
        assert_eq!(v["operating_point"]["inputs"], serde_json::json!({}));
        assert_eq!(v["accuracy"], Value::Null);
        for p in v["poles"].as_array().unwrap() {
            assert_eq!(p["time_constant_s"], Value::Null, "{p}");
            assert_eq!(p["damping_ratio"].as_f64(), Some(0.0), "{p}");
            assert!((p["frequency_rad_s"].as_f64().unwrap() - 3.0).abs() < 1e-12, "{p}");
        }
        // No states at all.
        let lin = model(&[], &[], &[], &[], &[], &[]);
        let v: Value = serde_json::from_str(&linearization_json(&lin)).expect("valid JSON");
        assert_eq!(v["A"], serde_json::json!([]));
        assert_eq!(v["poles"], serde_json::json!([]));
    }

    #[test]
    fn damping_report_shows_pairs_once() {
        // An oscillator (w = 2, zeta = 0.2) and a real pole at -0.5.
        let lin = model(
            &[&[0.0, 1.0, 0.0], &[-4.0, -0.8, 0.0], &[0.0, 0.0, -0.5]],
            &[&[0.0], &[1.0], &[1.0]],
            &[&[1.0, 0.0, 1.0]],
            &[&[0.0]],
            &["u"],
            &["y"],
        );
        let report = damping_report(&lin);
        let lines: Vec<&str> = report.lines().collect();
        assert_eq!(lines.len(), 4, "{report}");
        for column in ["Pole", "DampingRatio", "Frequency [rad/s]", "Frequency [Hz]", "TimeConstant [s]"] {
            assert!(lines[0].contains(column), "{report}");
        }
        assert!(lines[1].starts_with("---"), "{report}");
        let cells = |line: &str| {
            line.split("  ").map(str::trim).filter(|s| !s.is_empty()).map(String::from).collect::<Vec<_>>()
        };
        assert_eq!(cells(lines[2]), ["-0.5", "1", "0.5", "0.0795775", "2"], "{report}");
        assert_eq!(cells(lines[3]), ["-0.4 ± 1.95959i", "0.2", "2", "0.31831", "2.5"], "{report}");
        // Aligned: every line ends in the same column.
        let ends: Vec<usize> = lines.iter().map(|l| l.chars().count()).collect();
        assert!(ends.iter().all(|&e| e == ends[0]), "{report}");
        let empty = damping_report(&model(&[], &[], &[], &[], &[], &[]));
        assert!(empty.contains("no poles"), "{empty}");
        let undamped = damping_report(&model(&[&[0.0, 1.0], &[-9.0, 0.0]], &[&[], &[]], &[], &[], &[], &[]));
        assert!(undamped.contains("0 ± 3i") && undamped.contains("inf"), "{undamped}");
    }

    #[test]
    fn general_numbers() {
        assert_eq!(general(0.0), "0");
        assert_eq!(general(-0.4), "-0.4");
        assert_eq!(general(1.0 / 3.0), "0.333333");
        assert_eq!(general(123456.0), "123456");
        assert_eq!(general(1234567.0), "1.23457e6");
        assert_eq!(general(1.5e-7), "1.5e-7");
        assert_eq!(general(f64::INFINITY), "inf");
    }

    #[test]
    fn bode_magnitude_and_phase_at_the_natural_frequency() {
        let (w, zeta) = (2.0, 0.2);
        let lin = oscillator(w, zeta);
        let exact = 1.0 / (2.0 * zeta * w * w);
        // The engine's response at w itself.
        let (re, im) = lin.frequency_response(0, 0, &[w])[0];
        assert!(rel(re.hypot(im), exact) < 1e-12, "{re} {im}");
        assert!(re.abs() < 1e-12 * exact && im < 0.0, "{re} {im}");
        // The sampled response the plot draws: the middle of 401 points of w/10 .. 10 w is w.
        let options = BodeOptions { points: 401, range: Some((w / 10.0, w * 10.0)), ..Default::default() };
        let r = bode_response(&lin, &options).unwrap();
        assert_eq!(r.frequencies.len(), 401);
        assert!(rel(r.frequencies[200], w) < 1e-14, "{}", r.frequencies[200]);
        assert_eq!((r.frequencies[0], r.frequencies[400]), (0.2, 20.0));
        let curve = &r.curves[0];
        assert_eq!((curve.input.as_str(), curve.output.as_str()), ("u", "y"));
        let gain = 10f64.powf(curve.magnitude_db[200] / 20.0);
        assert!(rel(gain, exact) < 1e-9, "{gain} vs {exact}");
        assert!((curve.phase_deg[200] + 90.0).abs() < 1e-9, "{}", curve.phase_deg[200]);
        // The phase falls from 0 to -180 and passes -90 at w.
        assert!(curve.phase_deg.windows(2).all(|p| p[1] < p[0]));
        assert!(curve.phase_deg[0] > -3.0 && curve.phase_deg[400] < -177.0);
        let k = curve.phase_deg.iter().position(|&p| p <= -90.0).unwrap();
        let (p0, p1) = (curve.phase_deg[k - 1], curve.phase_deg[k]);
        let (l0, l1) = (r.frequencies[k - 1].ln(), r.frequencies[k].ln());
        let crossing = (l0 + (l1 - l0) * (-90.0 - p0) / (p1 - p0)).exp();
        assert!(rel(crossing, w) < 1e-5, "{crossing}");
        // Low frequencies: the static gain 1 / w^2.
        let g0 = 10f64.powf(curve.magnitude_db[0] / 20.0);
        let exact0 = 1.0 / ((w * w - 0.04).powi(2) + (2.0 * zeta * w * 0.2).powi(2)).sqrt();
        assert!(rel(g0, exact0) < 1e-9, "{g0} vs {exact0}");
    }

    #[test]
    fn phase_is_unwrapped_past_minus_180() {
        // 1 / (s + 1)^3: the phase goes to -270 degrees (-3 atan w).
        let lin = model(
            &[&[-1.0, 1.0, 0.0], &[0.0, -1.0, 1.0], &[0.0, 0.0, -1.0]],
            &[&[0.0], &[0.0], &[1.0]],
            &[&[1.0, 0.0, 0.0]],
            &[&[0.0]],
            &["u"],
            &["y"],
        );
        let r = bode_response(&lin, &BodeOptions { points: 50, range: Some((0.01, 1000.0)), ..Default::default() })
            .unwrap();
        for (&w, &p) in r.frequencies.iter().zip(&r.curves[0].phase_deg) {
            let exact = -3.0 * w.atan().to_degrees();
            assert!((p - exact).abs() < 1e-9, "at {w}: {p} vs {exact}");
        }
        let mut phase = vec![170.0, -170.0, f64::NAN, 150.0, 10.0 - 720.0];
        unwrap_degrees(&mut phase);
        assert_eq!(phase[..2], [170.0, 190.0]);
        assert!(phase[2].is_nan());
        assert_eq!(phase[3..], [150.0, 10.0]);
    }

    #[test]
    fn default_range_from_the_poles() {
        assert_eq!(default_frequency_range(&oscillator(2.0, 0.2)), (0.2, 20.0));
        // Poles at 0 and -5: the one at zero does not count.
        let lin = model(&[&[0.0, 1.0], &[0.0, -5.0]], &[&[0.0], &[1.0]], &[&[1.0, 0.0]], &[&[0.0]], &["u"], &["y"]);
        let (lo, hi) = default_frequency_range(&lin);
        assert!(rel(lo, 0.5) < 1e-12 && rel(hi, 50.0) < 1e-12, "{lo} {hi}");
        // A double integrator and a pure gain: no poles away from zero.
        let lin = model(&[&[0.0, 1.0], &[0.0, 0.0]], &[&[0.0], &[1.0]], &[&[1.0, 0.0]], &[&[0.0]], &["u"], &["y"]);
        assert_eq!(default_frequency_range(&lin), (0.01, 100.0));
        let gain = model(&[], &[], &[&[]], &[&[2.0]], &["u"], &["y"]);
        assert_eq!(default_frequency_range(&gain), (0.01, 100.0));
        let r = bode_response(&gain, &BodeOptions { points: 5, ..Default::default() }).unwrap();
        assert!(r.curves[0].magnitude_db.iter().all(|&m| rel(m, 20.0 * 2f64.log10()) < 1e-12));
    }

    /// Two inputs, two outputs: u1 drives the oscillator, u2 adds to y2 directly.
    fn two_by_two() -> Linearization {
        model(
            &[&[0.0, 1.0], &[-4.0, -0.8]],
            &[&[0.0, 0.0], &[1.0, 0.0]],
            &[&[1.0, 0.0], &[0.0, 1.0]],
            &[&[0.0, 0.0], &[0.0, 3.0]],
            &["u1", "u2"],
            &["y1", "y2"],
        )
    }

    #[test]
    fn png_has_the_requested_size() {
        let options = BodeOptions { width: 480, height: 360, points: 60, ..Default::default() };
        let (bytes, summary) = bode_png("oscillator", &two_by_two(), &options).unwrap();
        assert_eq!((summary.width, summary.height, summary.points), (480, 360, 60));
        assert_eq!(summary.range, (0.2, 20.0));
        // Every pair, y2 from u1 included, and u1 -> y2 whose gain is zero.
        assert_eq!(summary.pairs.len(), 4);
        let decoder = png::Decoder::new(bytes.as_slice());
        let reader = decoder.read_info().unwrap();
        let info = reader.info();
        assert_eq!((info.width, info.height), (480, 360));
    }

    #[test]
    fn svg_names_the_pairs_in_the_legend() {
        let options = BodeOptions {
            width: 400,
            height: 300,
            points: 40,
            pairs: Some(vec![("u1".into(), "y1".into()), ("u2".into(), "y2".into())]),
            ..Default::default()
        };
        let (text, summary) = bode_svg("two by two", &two_by_two(), &options).unwrap();
        assert_eq!(summary.pairs, [("u1".to_string(), "y1".to_string()), ("u2".to_string(), "y2".to_string())]);
        // plotters escapes `>` in text.
        assert!(text.contains("u1 -&gt; y1") && text.contains("u2 -&gt; y2"), "{text}");
        assert!(!text.contains("u1 -&gt; y2"));
        assert!(text.contains("magnitude [dB]") && text.contains("phase [deg]") && text.contains("two by two"));
    }

    #[test]
    fn write_bode_by_extension() {
        let dir = std::env::temp_dir().join(format!("multibody-view-bode-{}", std::process::id()));
        let options = BodeOptions { width: 300, height: 240, points: 20, ..Default::default() };
        let lin = oscillator(2.0, 0.2);
        let svg = dir.join("sub/bode.svg");
        write_bode(&svg, "t", &lin, &options).unwrap();
        assert!(std::fs::read_to_string(&svg).unwrap().starts_with("<svg"));
        let png = dir.join("bode.png");
        write_bode(&png, "t", &lin, &options).unwrap();
        assert!(std::fs::read(&png).unwrap().starts_with(b"\x89PNG"));
        assert!(matches!(write_bode(dir.join("bode.pdf"), "t", &lin, &options), Err(ViewError::Format { .. })));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn refuses_what_it_cannot_draw() {
        let message = |lin: &Linearization, options: &BodeOptions| match bode_svg("t", lin, options) {
            Err(e) => e.to_string(),
            Ok(_) => panic!("drawn"),
        };
        let options = BodeOptions { points: 10, ..Default::default() };
        let no_inputs = model(&[&[-1.0]], &[&[]], &[&[1.0]], &[&[]], &[], &["y"]);
        let m = message(&no_inputs, &options);
        assert!(m.contains("no inputs") && m.contains("--inputs") && !m.contains("no outputs"), "{m}");
        let no_outputs = model(&[&[-1.0]], &[&[1.0]], &[], &[], &["u"], &[]);
        let m = message(&no_outputs, &options);
        assert!(m.contains("no outputs") && m.contains("--outputs") && !m.contains("no inputs"), "{m}");
        let neither = model(&[&[-1.0]], &[&[]], &[], &[], &[], &[]);
        let m = message(&neither, &options);
        assert!(m.contains("no inputs and no outputs"), "{m}");
        let lin = two_by_two();
        let pairs = |i: &str, o: &str| BodeOptions { pairs: Some(vec![(i.into(), o.into())]), ..options.clone() };
        let m = message(&lin, &pairs("u3", "y1"));
        assert!(m.contains("`u3` is not an input") && m.contains("u1, u2"), "{m}");
        let m = message(&lin, &pairs("u1", "z"));
        assert!(m.contains("`z` is not an output") && m.contains("y1, y2"), "{m}");
        let m = message(&lin, &BodeOptions { range: Some((0.0, 10.0)), ..options.clone() });
        assert!(m.contains("0 < low < high"), "{m}");
        let m = message(&lin, &BodeOptions { range: Some((10.0, 1.0)), ..options.clone() });
        assert!(m.contains("0 < low < high"), "{m}");
    }
}
