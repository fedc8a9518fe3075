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

    /// Rows buffered before they go out as one record batch.
    const BATCH: usize = 8192;
    /// Rows of a row group, which the writer holds until it is full: small
    /// enough that a long run's memory stays bounded.
    const ROW_GROUP: usize = 2 * BATCH;

    pub struct ParquetTable {
        writer: ArrowWriter<NamedTempFile>,
        schema: Arc<Schema>,
        columns: Vec<Vec<f64>>,
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
            let properties = WriterProperties::builder()
                .set_compression(Compression::SNAPPY)
                .set_max_row_group_row_count(Some(ROW_GROUP))
                // Samples of a simulation seldom repeat: dictionaries would only cost memory.
                .set_dictionary_enabled(false)
                .build();
            let writer = ArrowWriter::try_new(file, schema.clone(), Some(properties)).map_err(io::Error::other)?;
            let columns = vec![Vec::with_capacity(BATCH); schema.fields().len()];
            Ok(Self { writer, schema, columns })
        }

        pub fn row(&mut self, keys: &[f64], t: f64, values: &[f64]) -> io::Result<()> {
            let row = keys.iter().chain(std::iter::once(&t)).chain(values);
            for (column, &x) in self.columns.iter_mut().zip(row) {
                column.push(x);
            }
            if self.columns[0].len() >= BATCH {
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
                .map(|c| Arc::new(Float64Array::from(std::mem::replace(c, Vec::with_capacity(BATCH)))) as ArrayRef)
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
