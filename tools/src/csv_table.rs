//! Every CSV the tools write (the report's files, `report --csv`, `tables --csv`), through the
//! `csv` crate's writer: a field with a comma, a quote or a line break is quoted (a method
//! called `Jakob-Hanika 2019 (pbrt-v4, Mitsuba 3)`, a light named `LED, warm` in a user's
//! file), and every row must have the header's number of fields.

use std::path::{Path, PathBuf};

use crate::Error;

/// A CSV table being built in memory: the header, then one [`row`](Table::row) at a time.
pub struct Table {
    writer: csv::Writer<Vec<u8>>,
    /// The first error (a row whose length differs from the header's), reported by
    /// [`into_string`](Table::into_string) and [`write`](Table::write).
    error: Option<csv::Error>,
}

impl Table {
    /// A table with this header, given as the header line (`"set,n,mean_de00"`): the names
    /// are split at the commas, so the source reads as the file's first line.
    pub fn new(header: &str) -> Table {
        let mut t = Table {
            writer: csv::WriterBuilder::new()
                .flexible(false)
                .from_writer(Vec::new()),
            error: None,
        };
        t.row(header.split(','));
        t
    }

    /// Adds a row; its fields are written as they are, quoted where CSV needs it.
    pub fn row<I>(&mut self, fields: I) -> &mut Table
    where
        I: IntoIterator,
        I::Item: AsRef<str>,
    {
        if self.error.is_none() {
            let fields: Vec<I::Item> = fields.into_iter().collect();
            let bytes = fields.iter().map(|f| f.as_ref().as_bytes());
            if let Err(e) = self.writer.write_record(bytes) {
                self.error = Some(e);
            }
        }
        self
    }

    /// The CSV text, or the first error.
    pub fn into_string(self) -> Result<String, csv::Error> {
        if let Some(e) = self.error {
            return Err(e);
        }
        let bytes = self.writer.into_inner().map_err(|e| e.into_error())?;
        // Every field came in as a `str`, and the writer adds only ASCII.
        Ok(String::from_utf8(bytes).expect("fields are UTF-8"))
    }

    /// Writes the table to `dir/name`; returns the path.
    pub fn write(self, dir: &Path, name: &str) -> Result<PathBuf, Error> {
        let path = dir.join(name);
        let write_error = |source| Error::Write {
            path: path.clone(),
            source,
        };
        let text = self
            .into_string()
            .map_err(|e| write_error(std::io::Error::other(e)))?;
        std::fs::write(&path, text).map_err(write_error)?;
        Ok(path)
    }

    /// Prints the table on standard output. A reader that stops early (`| head`) is not an
    /// error.
    pub fn print(self) -> Result<(), Error> {
        use std::io::Write as _;
        let write_error = |source| Error::Write {
            path: PathBuf::from("standard output"),
            source,
        };
        let text = self
            .into_string()
            .map_err(|e| write_error(std::io::Error::other(e)))?;
        let mut out = std::io::stdout().lock();
        match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
            Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => Err(write_error(e)),
            _ => Ok(()),
        }
    }
}
