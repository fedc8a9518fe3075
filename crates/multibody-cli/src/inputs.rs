//! `--input NAME=table.csv`: drives a model input from a table of time and
//! value. The model's `Input` component of that name becomes a
//! `BlockComponents.TimeTable` before assembly, so the table is
//! interpolated linearly and its corners are time events of the run (the
//! integrator stops exactly at each).

use crate::exit::Failure;
use multibody::files::{self, Fifo, OpenError, FIFO_WAIT};
use multibody::{Model, SimulationOptions, Value};
use std::path::Path;

/// The kind of a model input, and of the table that replaces it.
const INPUT: &str = "Input";
const TABLE: &str = "BlockComponents.TimeTable";

/// Replaces each input named in `given` (`NAME=FILE`) by the table read
/// from its file, checked against the run's time span.
pub fn drive(model: &mut Model, given: &[String], options: &SimulationOptions) -> Result<(), Failure> {
    let mut done: Vec<&str> = Vec::new();
    for arg in given {
        let Some((name, file)) = arg.split_once('=').filter(|(n, f)| !n.trim().is_empty() && !f.is_empty()) else {
            return Err(Failure::Usage(format!("--input {arg}: write NAME=FILE.csv, e.g. --input tau=torque.csv")));
        };
        let name = name.trim();
        if done.contains(&name) {
            return Err(Failure::Usage(format!("--input {name} is given twice")));
        }
        let inputs: Vec<&str> = model.components.iter().filter(|c| c.kind == INPUT).map(|c| c.name.as_str()).collect();
        if !inputs.contains(&name) {
            return Err(Failure::Usage(unknown_input(name, &inputs)));
        }
        let text = read_table(name, file)?;
        let rows = parse_table(file, &text).map_err(Failure::Usage)?;
        check_span(file, &rows, options).map_err(Failure::Usage)?;
        let component = model.components.iter_mut().find(|c| c.name == name).expect("found above");
        component.kind = TABLE.to_string();
        component.params = vec![("table".to_string(), Value::Matrix(rows.iter().map(|&(t, x)| vec![t, x]).collect()))];
        done.push(name);
    }
    Ok(())
}

/// The most a table may hold: 1 GB is some 30 million rows.
const TABLE_MAX_BYTES: u64 = 1 << 30;

/// The text of the table of `--input NAME=FILE`, read through
/// [`multibody::files::read`]: a FIFO (`<(...)`) is read once something
/// writes to it, within `FIFO_WAIT` (opening one that nothing writes to
/// blocked for ever); a folder, a device or a socket is refused.
fn read_table(name: &str, file: &str) -> Result<String, Failure> {
    let option = format!("--input {name}={file}");
    let bytes = files::read(Path::new(file), Fifo::Wait(FIFO_WAIT), TABLE_MAX_BYTES).map_err(|e| match e {
        OpenError::Io(e) => Failure::Io(format!("{option}: cannot read {file}: {e}")),
        OpenError::NotAFile(kind) => Failure::Usage(format!(
            "{option}: {file} is {}, not a table; give the path of a CSV file of time and value",
            kind.describe()
        )),
        OpenError::NoWriter { waited } => Failure::Io(format!(
            "{option}: nothing writes to the FIFO {file} (waited {} s); start the program that writes the table \
             first, or give the path of a CSV file",
            waited.as_secs()
        )),
        OpenError::TooLarge { .. } => Failure::Usage(format!(
            "{option}: {file} holds more than {} MB, more than a table of time and value this command reads; \
             thin the table out (linear interpolation needs a row only where the slope changes)",
            TABLE_MAX_BYTES >> 20
        )),
    })?;
    String::from_utf8(bytes).map_err(|e| {
        Failure::Usage(format!(
            "{option}: {file} is not UTF-8 text (byte {}); write the table as CSV text",
            e.utf8_error().valid_up_to()
        ))
    })
}

fn unknown_input(name: &str, inputs: &[&str]) -> String {
    if inputs.is_empty() {
        return format!(
            "--input {name}: the model has no inputs (declare one as a RealInput of the simulated component: \
             `{name} = RealInput()`)"
        );
    }
    let hint = multibody::closest(name, inputs.iter().copied())
        .first()
        .map_or(String::new(), |c| format!("; did you mean `{c}`?"));
    format!("--input {name}: the model has no input `{name}`{hint} (its inputs: {})", inputs.join(", "))
}

/// The rows `(time, value)` of a CSV table: a header line (optional), then
/// two numbers a line, times increasing. Empty lines and lines starting
/// with `#` are skipped. Errors name the file and the line.
pub fn parse_table(file: &str, text: &str) -> Result<Vec<(f64, f64)>, String> {
    let mut rows: Vec<(f64, f64)> = Vec::new();
    let mut header_seen = false;
    for (k, line) in text.lines().enumerate() {
        let at = format!("{file}:{}", k + 1);
        let line = line.trim().trim_start_matches('\u{feff}');
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let fields: Vec<&str> = line.split(',').map(str::trim).collect();
        if fields.len() != 2 {
            return Err(format!("{at}: expected 2 columns (time, value), found {}: `{line}`", fields.len()));
        }
        let numbers: Vec<Result<f64, _>> = fields.iter().map(|f| f.parse::<f64>()).collect();
        if !header_seen && rows.is_empty() && numbers.iter().all(Result::is_err) {
            header_seen = true; // the header: column names
            continue;
        }
        let mut row = [0.0; 2];
        for ((x, field), what) in row.iter_mut().zip(&fields).zip(["time", "value"]) {
            *x = field.parse::<f64>().map_err(|_| format!("{at}: the {what} `{field}` is not a number"))?;
            if !x.is_finite() {
                return Err(format!("{at}: the {what} is {field}; the table needs finite numbers"));
            }
        }
        if let Some(&(previous, _)) = rows.last() {
            if row[0] <= previous {
                return Err(format!(
                    "{at}: the time {} does not come after the previous row's {previous}: the times must increase",
                    row[0]
                ));
            }
        }
        rows.push((row[0], row[1]));
    }
    if rows.len() < 2 {
        return Err(format!(
            "{file}: the table needs at least 2 rows of (time, value) to interpolate between; it has {}",
            rows.len()
        ));
    }
    Ok(rows)
}

/// The table must cover the run: no value is made up outside it.
fn check_span(file: &str, rows: &[(f64, f64)], options: &SimulationOptions) -> Result<(), String> {
    let (first, last) = (rows[0].0, rows[rows.len() - 1].0);
    if first > options.start || last < options.stop {
        return Err(format!(
            "{file}: the table covers t = {first} … {last} s, but the run goes from t = {} to {} s; extend the \
             table, or run within it (--stop)",
            options.start, options.stop
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_a_table_with_or_without_a_header() {
        let rows = parse_table("t.csv", "time,tau\n0,1\n0.5, 2\n\n# note\n1,3\n").unwrap();
        assert_eq!(rows, vec![(0.0, 1.0), (0.5, 2.0), (1.0, 3.0)]);
        assert_eq!(parse_table("t.csv", "0,1\n1,2").unwrap().len(), 2);
    }

    #[test]
    fn bad_tables_name_the_file_and_line() {
        let err = |text: &str| parse_table("t.csv", text).unwrap_err();
        assert!(
            err("t,x\n0,1\n2,1\n1,1\n").starts_with("t.csv:4: the time 1 does not come after"),
            "{}",
            err("t,x\n0,1\n2,1\n1,1\n")
        );
        assert!(err("t,x\n0,1\n1,NaN\n").starts_with("t.csv:3: the value is NaN"));
        assert!(err("t,x\n0,1\n1,abc\n").starts_with("t.csv:3: the value `abc` is not a number"));
        assert!(err("t,x\n0,1,2\n").starts_with("t.csv:2: expected 2 columns"));
        assert!(err("t,x\n0,1\n").contains("at least 2 rows"));
    }

    #[test]
    fn the_table_must_cover_the_run() {
        let options = SimulationOptions { start: 0.0, stop: 2.0, ..Default::default() };
        let e = check_span("t.csv", &[(0.0, 1.0), (1.0, 2.0)], &options).unwrap_err();
        assert!(e.contains("covers t = 0 … 1 s") && e.contains("from t = 0 to 2 s"), "{e}");
        assert!(check_span("t.csv", &[(-1.0, 1.0), (2.0, 2.0)], &options).is_ok());
    }
}
