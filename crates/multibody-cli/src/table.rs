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

    /// Whether rows may be rendered before they are written
    /// ([`multibody::simulate::csv_row`], on the threads that computed
    /// them) and added with [`TableWriter::rendered_rows`].
    pub fn takes_rendered_rows(&self) -> bool {
        matches!(self, TableWriter::Csv(_))
    }

    /// Rows rendered by [`multibody::simulate::csv_row`] (a CSV table only).
    pub fn rendered_rows(&mut self, rows: &[u8]) -> io::Result<()> {
        match self {
            TableWriter::Csv(csv) => csv.rendered_rows(rows),
            #[cfg(feature = "parquet")]
            TableWriter::Parquet(_) => Err(io::Error::other("a Parquet table takes values, not rendered rows")),
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
    use parquet::basic::{Compression, Repetition, Type as PhysicalType};
    use parquet::data_type::DoubleType;
    use parquet::file::properties::{EnabledStatistics, WriterProperties};
    use parquet::file::writer::SerializedFileWriter;
    use parquet::schema::types::Type;
    use std::io;
    use std::sync::Arc;
    use tempfile::NamedTempFile;

    /// The most rows buffered before they go out as one row group.
    const ROWS: usize = 16384;
    /// Bytes the buffered rows may hold: a wide table (every signal of a
    /// long chain, 10^5 columns) gets row groups of a few rows, not 16384
    /// rows of gigabytes.
    const BUFFER_BYTES: usize = 32 << 20;
    /// What the writer keeps of each column chunk until the footer is
    /// written (measured with parquet 60 on 198,019 columns, statistics and
    /// page index off: about 730 bytes), and of each column for the whole
    /// run (the schema and its descriptors: about 810 bytes).
    const CHUNK_BYTES: usize = 800;
    const COLUMN_BYTES: usize = 1000;

    /// Above this many columns a table is written without statistics and
    /// page index (see `ParquetTable::new`).
    const WIDE: usize = 4096;

    /// Rows per row group for `columns` columns. Each row group costs the
    /// footer `CHUNK_BYTES` a column; a wide table buffers at least that
    /// much, so that the footer does not outgrow the rows it describes.
    pub fn group_rows(columns: usize) -> usize {
        let buffer = BUFFER_BYTES.max(columns * CHUNK_BYTES);
        (buffer / (8 * columns.max(1))).clamp(1, ROWS)
    }

    /// About what writing `samples` rows of `columns` columns holds in
    /// memory: the buffered rows, the schema and its descriptors, and the
    /// footer's description of every column chunk of every row group. (The
    /// columns are written one at a time, so a wide table does not hold an
    /// encoder per column.)
    pub fn memory(samples: f64, columns: usize) -> f64 {
        let rows = group_rows(columns);
        let groups = (samples / rows as f64).ceil().max(1.0);
        let buffered = (rows as f64).min(samples.max(1.0)) * columns as f64 * 8.0;
        buffered + (columns * COLUMN_BYTES) as f64 + groups * (columns * CHUNK_BYTES) as f64
    }

    pub struct ParquetTable {
        writer: SerializedFileWriter<NamedTempFile>,
        columns: Vec<Vec<f64>>,
        rows: usize,
    }

    impl ParquetTable {
        pub fn new(file: NamedTempFile, keys: &[&str], names: &[&str]) -> io::Result<Self> {
            let fields = keys
                .iter()
                .chain(&["time"])
                .chain(names)
                .map(|name| {
                    Type::primitive_type_builder(name, PhysicalType::DOUBLE)
                        .with_repetition(Repetition::REQUIRED)
                        .build()
                        .map(Arc::new)
                })
                .collect::<Result<Vec<_>, _>>()
                .map_err(io::Error::other)?;
            let count = fields.len();
            let schema = Type::group_type_builder("schema").with_fields(fields).build().map_err(io::Error::other)?;
            let wide = count > WIDE;
            let properties = WriterProperties::builder()
                .set_compression(Compression::SNAPPY)
                // Samples of a simulation seldom repeat: dictionaries would only cost memory.
                .set_dictionary_enabled(false)
                // The writer keeps each column chunk's statistics and page
                // index to the end: for a wide table that grows by about
                // 1 kB a column with every row group.
                .set_statistics_enabled(if wide { EnabledStatistics::None } else { EnabledStatistics::Page })
                .set_offset_index_disabled(wide)
                .build();
            let writer =
                SerializedFileWriter::new(file, Arc::new(schema), Arc::new(properties)).map_err(io::Error::other)?;
            let rows = group_rows(count);
            Ok(Self { writer, columns: vec![Vec::with_capacity(rows); count], rows })
        }

        pub fn row(&mut self, keys: &[f64], t: f64, values: &[f64]) -> io::Result<()> {
            let row = keys.iter().chain(std::iter::once(&t)).chain(values);
            for (column, &x) in self.columns.iter_mut().zip(row) {
                column.push(x);
            }
            if self.columns[0].len() >= self.rows {
                self.write_group()?;
            }
            Ok(())
        }

        /// The buffered rows as one row group, written column by column.
        fn write_group(&mut self) -> io::Result<()> {
            if self.columns.first().is_none_or(|c| c.is_empty()) {
                return Ok(());
            }
            let mut group = self.writer.next_row_group().map_err(io::Error::other)?;
            let mut k = 0;
            while let Some(mut column) = group.next_column().map_err(io::Error::other)? {
                column.typed::<DoubleType>().write_batch(&self.columns[k], None, None).map_err(io::Error::other)?;
                column.close().map_err(io::Error::other)?;
                self.columns[k].clear();
                k += 1;
            }
            group.close().map_err(io::Error::other)?;
            Ok(())
        }

        pub fn finish(mut self) -> io::Result<NamedTempFile> {
            self.write_group()?;
            self.writer.into_inner().map_err(io::Error::other)
        }
    }
}
