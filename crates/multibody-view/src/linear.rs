//! Views of a linear model ([`Linearization`]): its matrices, operating
//! point and poles as JSON, a damping table for the terminal (the columns
//! of Dyad's DampReport), and a Bode plot (PNG or SVG, drawn with plotters
//! like the signal plots).

use crate::json::Json;
use multibody::{Linearization, Pole};
use std::fmt::Write;

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
}
