//! Result tables as they are written: CSV, or Parquet for `.parquet` (the
//! same columns: keys of a sweep, `time`, then the signals, all f64), row
//! by row, so that a long run needs no memory for its samples.

use multibody::simulate::CsvWriter;
use std::io::{self, BufWriter};
use std::path::Path;
use tempfile::NamedTempFile;

/// The format a path asks for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    Csv,
    Parquet,
}

impl Format {
    pub fn of(path: &Path) -> Format {
        match path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase).as_deref() {
            Some("parquet" | "pq") => Format::Parquet,
            _ => Format::Csv,
        }
    }
}

/// A table being written into a temporary file.
pub enum TableWriter {
    Csv(CsvWriter<BufWriter<NamedTempFile>>),
    #[cfg(feature = "parquet")]
    Parquet(Box<parquet_table::ParquetTable>),
}

impl TableWriter {
    /// Starts a table with `keys` columns before `time`, then `names`.
    pub fn new(format: Format, file: NamedTempFile, keys: &[&str], names: &[&str]) -> io::Result<Self> {
        match format {
            Format::Csv => Ok(TableWriter::Csv(CsvWriter::with_keys(BufWriter::new(file), keys, names)?)),
            #[cfg(feature = "parquet")]
            Format::Parquet => Ok(TableWriter::Parquet(Box::new(parquet_table::ParquetTable::new(file, keys, names)?))),
            #[cfg(not(feature = "parquet"))]
            Format::Parquet => {
                Err(io::Error::other("this build of multibody writes no Parquet (built without the `parquet` feature)"))
            }
        }
    }

    pub fn row(&mut self, keys: &[f64], t: f64, values: &[f64]) -> io::Result<()> {
        match self {
            TableWriter::Csv(csv) => csv.keyed_row(keys, t, values),
            #[cfg(feature = "parquet")]
            TableWriter::Parquet(table) => table.row(keys, t, values),
        }
    }

    /// About the memory writing `samples` rows of `columns` columns in
    /// `format` holds (a CSV streams: a buffer).
    pub fn memory(format: Format, samples: f64, columns: usize) -> f64 {
        match format {
            Format::Csv => 0.0,
            #[cfg(feature = "parquet")]
            Format::Parquet => parquet_table::memory(samples, columns),
            #[cfg(not(feature = "parquet"))]
            Format::Parquet => 0.0,
        }
    }

    /// Ends the table (Parquet: its footer) and gives the file.
    pub fn finish(self) -> io::Result<NamedTempFile> {
        match self {
            TableWriter::Csv(csv) => csv.finish()?.into_inner().map_err(|e| e.into_error()),
            #[cfg(feature = "parquet")]
            TableWriter::Parquet(table) => table.finish(),
        }
    }
}

#[cfg(feature = "parquet")]
mod parquet_table {
    use arrow_array::{ArrayRef, Float64Array, RecordBatch};
    use arrow_schema::{DataType, Field, Schema};
    use parquet::arrow::ArrowWriter;
    use parquet::basic::Compression;
    use parquet::file::properties::WriterProperties;
    use std::io;
    use std::sync::Arc;
    use tempfile::NamedTempFile;

    /// The most rows buffered before they go out as one record batch.
    const BATCH: usize = 8192;
    /// Bytes a batch may hold: a wide table (every signal of a long chain,
    /// 10^5 columns) gets batches of a few rows, not 8192 rows of gigabytes.
    const BATCH_BYTES: usize = 16 << 20;

    /// Rows per record batch for `columns` columns; a row group holds two
    /// batches (the writer keeps it until it is full).
    pub fn batch_rows(columns: usize) -> usize {
        (BATCH_BYTES / (8 * columns.max(1))).clamp(1, BATCH)
    }

    /// About what writing `samples` rows of `columns` columns holds in
    /// memory: the batch, the row group being encoded, the footer's
    /// description of every column chunk of every row group (which the
    /// writer keeps to the end: about 200 bytes each), and the writer's
    /// own state per column (measured: about 6.5 kB, so a table of 10^5
    /// columns costs 650 MB before its first row).
    pub fn memory(samples: f64, columns: usize) -> f64 {
        let rows = batch_rows(columns);
        let groups = (samples / (2 * rows) as f64).ceil().max(1.0);
        (3 * rows * columns * 8) as f64 + groups * columns as f64 * 200.0 + columns as f64 * 6.5e3
    }

    pub struct ParquetTable {
        writer: ArrowWriter<NamedTempFile>,
        schema: Arc<Schema>,
        columns: Vec<Vec<f64>>,
        batch: usize,
    }

    impl ParquetTable {
        pub fn new(file: NamedTempFile, keys: &[&str], names: &[&str]) -> io::Result<Self> {
            let fields: Vec<Field> = keys
                .iter()
                .chain(&["time"])
                .chain(names)
                .map(|name| Field::new(name.to_string(), DataType::Float64, false))
                .collect();
            let schema = Arc::new(Schema::new(fields));
            let batch = batch_rows(schema.fields().len());
            let properties = WriterProperties::builder()
                .set_compression(Compression::SNAPPY)
                .set_max_row_group_row_count(Some(2 * batch))
                // Samples of a simulation seldom repeat: dictionaries would only cost memory.
                .set_dictionary_enabled(false)
                .build();
            let writer = ArrowWriter::try_new(file, schema.clone(), Some(properties)).map_err(io::Error::other)?;
            let columns = vec![Vec::with_capacity(batch); schema.fields().len()];
            Ok(Self { writer, schema, columns, batch })
        }

        pub fn row(&mut self, keys: &[f64], t: f64, values: &[f64]) -> io::Result<()> {
            let row = keys.iter().chain(std::iter::once(&t)).chain(values);
            for (column, &x) in self.columns.iter_mut().zip(row) {
                column.push(x);
            }
            if self.columns[0].len() >= self.batch {
                self.flush_batch()?;
            }
            Ok(())
        }

        fn flush_batch(&mut self) -> io::Result<()> {
            if self.columns.first().is_none_or(|c| c.is_empty()) {
                return Ok(());
            }
            let arrays: Vec<ArrayRef> = self
                .columns
                .iter_mut()
                .map(|c| Arc::new(Float64Array::from(std::mem::replace(c, Vec::with_capacity(self.batch)))) as ArrayRef)
                .collect();
            let batch = RecordBatch::try_new(self.schema.clone(), arrays).map_err(io::Error::other)?;
            self.writer.write(&batch).map_err(io::Error::other)
        }

        pub fn finish(mut self) -> io::Result<NamedTempFile> {
            self.flush_batch()?;
            self.writer.into_inner().map_err(io::Error::other)
        }
    }
}
