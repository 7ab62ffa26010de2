//! Tables as Parquet files: written whole under a temporary name and
//! renamed ([`write`], [`Appender`], [`AtomicTableWriter`]), read back as
//! typed rows ([`read`]) with their metadata checked.

use std::fs::{self, File};
use std::io;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use arrow_array::RecordBatch;
use arrow_schema::Schema;
use parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder;
use parquet::arrow::ArrowWriter;
use parquet::basic::{Compression, ZstdLevel};
use parquet::file::metadata::KeyValue;
use parquet::file::properties::WriterProperties;

use super::error::TableError;
use super::table::{Table, TableKind, ROW_GROUP_ROWS};

/// Key-value metadata keys written into every table.
pub const META_TABLE: &str = "rocking.table";
pub const META_SCHEMA_VERSION: &str = "rocking.schema_version";
pub const META_CRATE_VERSION: &str = "rocking.crate_version";

/// zstd level for every table: level 3 is zstd's default, a good
/// speed/size balance for float columns.
const ZSTD_LEVEL: i32 = 3;

/// Rows per batch as a table is read back.
pub const READ_BATCH_ROWS: usize = 1024;

/// Rows of a `T` table converted to Arrow batches by
/// [`Appender::rows_as_read`], to be written again as they are.
pub struct Batches<T> {
    batches: Vec<RecordBatch>,
    kind: std::marker::PhantomData<fn(&T)>,
}

impl<T> Batches<T> {
    /// How many rows they hold.
    pub fn rows(&self) -> usize {
        self.batches.iter().map(RecordBatch::num_rows).sum()
    }
}

/// The writer's properties of every table: zstd, row groups of
/// [`ROW_GROUP_ROWS`], the metadata (table, schema and crate versions, and
/// `settings`).
fn properties(kind: TableKind, settings: &[(String, String)]) -> WriterProperties {
    let mut kv = vec![
        KeyValue::new(META_TABLE.to_string(), kind.name.to_string()),
        KeyValue::new(
            META_SCHEMA_VERSION.to_string(),
            kind.schema_version.to_string(),
        ),
        KeyValue::new(
            META_CRATE_VERSION.to_string(),
            env!("CARGO_PKG_VERSION").to_string(),
        ),
    ];
    kv.extend(
        settings
            .iter()
            .map(|(k, v)| KeyValue::new(k.clone(), v.clone())),
    );
    WriterProperties::builder()
        .set_compression(Compression::ZSTD(
            ZstdLevel::try_new(ZSTD_LEVEL).expect("zstd level 3 is valid"),
        ))
        .set_key_value_metadata(Some(kv))
        .set_max_row_group_row_count(Some(ROW_GROUP_ROWS))
        .build()
}

/// `rows` as the bytes of a Parquet file, written as [`write`] writes a
/// file (the same schema, metadata and compression): for a front end that
/// hands a table on in memory, its columns typed (Python).
pub fn to_bytes<T: Table>(
    rows: &[T],
    settings: &[(String, String)],
) -> Result<Vec<u8>, TableError> {
    let path = || PathBuf::from("(a table in memory)");
    let mut bytes = Vec::new();
    let mut w = ArrowWriter::try_new(&mut bytes, T::schema(), Some(properties(T::KIND, settings)))
        .map_err(|source| TableError::Parquet {
            path: path(),
            source,
        })?;
    for chunk in rows.chunks(T::BATCH_ROWS) {
        let batch = T::to_batch(chunk).map_err(|source| TableError::Arrow {
            path: path(),
            source,
        })?;
        w.write(&batch).map_err(|source| TableError::Parquet {
            path: path(),
            source,
        })?;
    }
    w.close().map_err(|source| TableError::Parquet {
        path: path(),
        source,
    })?;
    Ok(bytes)
}

/// Writes `batches` to `dest` atomically, with `settings` in the metadata.
pub fn write_batches<T: Table>(
    dest: &Path,
    batches: &Batches<T>,
    settings: &[(String, String)],
) -> Result<(), TableError> {
    let mut w = Appender::<T>::create(dest, settings)?;
    w.append(batches)?;
    w.commit()
}

/// Writes `rows` to `dest` atomically, with `settings` in the metadata.
pub fn write<T: Table>(
    dest: &Path,
    rows: &[T],
    settings: &[(String, String)],
) -> Result<(), TableError> {
    let mut w = Appender::<T>::create(dest, settings)?;
    w.rows(rows)?;
    w.commit()
}

/// A table written in pieces, in order (rows from memory, or whole tables
/// of the same kind read back from files), then committed atomically: until
/// [`Appender::commit`], nothing is under `dest` (a dropped appender removes
/// its temporary file).
pub struct Appender<T> {
    dest: PathBuf,
    w: AtomicTableWriter,
    rows: std::marker::PhantomData<fn(&T)>,
}

impl<T: Table> Appender<T> {
    /// Starts `dest`, with `settings` in the metadata.
    pub fn create(dest: &Path, settings: &[(String, String)]) -> Result<Self, TableError> {
        Ok(Appender {
            dest: dest.to_path_buf(),
            w: AtomicTableWriter::create(dest, T::KIND, T::schema(), settings)?,
            rows: std::marker::PhantomData,
        })
    }

    /// Appends `rows`.
    pub fn rows(&mut self, rows: &[T]) -> Result<(), TableError> {
        self.batches(rows, T::BATCH_ROWS.max(1))
    }

    /// Appends `rows` as [`Appender::table`] appends them from a file that
    /// holds just them (in batches of [`READ_BATCH_ROWS`]): the Parquet
    /// writer's pages follow its input's batches, so a table assembled from
    /// such pieces is the same to the byte whether each came from memory
    /// or from a file. Returns the batches, to write `rows` elsewhere too
    /// ([`write_batches`]) without converting them again.
    pub fn rows_as_read(&mut self, rows: &[T]) -> Result<Batches<T>, TableError> {
        let batches = rows
            .chunks(READ_BATCH_ROWS)
            .map(|chunk| self.convert(chunk))
            .collect::<Result<Vec<_>, _>>()?;
        let batches = Batches {
            batches,
            kind: std::marker::PhantomData,
        };
        self.append(&batches)?;
        Ok(batches)
    }

    /// Appends `rows` in batches of `per` rows.
    fn batches(&mut self, rows: &[T], per: usize) -> Result<(), TableError> {
        for chunk in rows.chunks(per) {
            let batch = self.convert(chunk)?;
            self.w.write(&batch)?;
        }
        Ok(())
    }

    /// `rows` as one Arrow batch; an error names this table's file.
    fn convert(&self, rows: &[T]) -> Result<RecordBatch, TableError> {
        T::to_batch(rows).map_err(|source| TableError::Arrow {
            path: self.dest.clone(),
            source,
        })
    }

    /// Appends rows already converted.
    pub fn append(&mut self, batches: &Batches<T>) -> Result<(), TableError> {
        for batch in &batches.batches {
            self.w.write(batch)?;
        }
        Ok(())
    }

    /// Appends every row of the `T` table at `path` (checked as [`read`] does).
    pub fn table(&mut self, path: &Path) -> Result<(), TableError> {
        for batch in read_table(path, T::KIND)?.batches {
            self.w.write(&batch)?;
        }
        Ok(())
    }

    /// Closes the file and moves it to `dest`.
    pub fn commit(self) -> Result<(), TableError> {
        self.w.commit()
    }
}

/// Reads every row of a table, checking that the file is this table at the
/// schema version this build reads.
pub fn read<T: Table>(path: &Path) -> Result<Vec<T>, TableError> {
    let mut rows = Vec::new();
    for batch in read_table(path, T::KIND)?.batches {
        rows.extend(T::from_batch(&batch, path)?);
    }
    Ok(rows)
}

/// [`read`] over several files (a dataset), in file order.
pub fn read_all<T: Table>(paths: &[impl AsRef<Path>]) -> Result<Vec<T>, TableError> {
    let mut rows = Vec::new();
    for p in paths {
        rows.extend(read::<T>(p.as_ref())?);
    }
    Ok(rows)
}

/// A Parquet file being written under a temporary name; [`commit`] makes it
/// appear at its destination, dropping it without commit removes it.
///
/// [`commit`]: AtomicTableWriter::commit
pub struct AtomicTableWriter {
    dest: PathBuf,
    tmp: PathBuf,
    writer: Option<ArrowWriter<File>>,
}

impl AtomicTableWriter {
    /// Starts writing `kind` with `schema` to a temporary file beside `dest`.
    /// `settings` are extra key-value pairs recorded in the file's metadata.
    pub fn create(
        dest: &Path,
        kind: TableKind,
        schema: Arc<Schema>,
        settings: &[(String, String)],
    ) -> Result<Self, TableError> {
        let io_err = |source| TableError::Io {
            path: dest.to_path_buf(),
            source,
        };
        if let Some(parent) = dest.parent().filter(|p| !p.as_os_str().is_empty()) {
            fs::create_dir_all(parent).map_err(io_err)?;
        }
        if dest.file_name().is_none() {
            return Err(io_err(io::Error::new(
                io::ErrorKind::InvalidInput,
                "not a file path",
            )));
        }
        let tmp = temporary_path(dest);
        let file = File::create(&tmp).map_err(|source| TableError::Io {
            path: tmp.clone(),
            source,
        })?;
        let props = properties(kind, settings);
        // Constructed before the writer so that a failure below removes the file.
        let mut this = AtomicTableWriter {
            dest: dest.to_path_buf(),
            tmp,
            writer: None,
        };
        let writer = ArrowWriter::try_new(file, schema, Some(props)).map_err(|source| {
            TableError::Parquet {
                path: this.tmp.clone(),
                source,
            }
        })?;
        this.writer = Some(writer);
        Ok(this)
    }

    /// Appends a batch; each call of at most the writer's row-group size
    /// keeps memory bounded by one row group.
    pub fn write(&mut self, batch: &RecordBatch) -> Result<(), TableError> {
        let writer = self.writer.as_mut().expect("writer is open until commit");
        writer.write(batch).map_err(|source| TableError::Parquet {
            path: self.tmp.clone(),
            source,
        })
    }

    /// Closes the file, syncs it and renames it to its destination.
    pub fn commit(mut self) -> Result<(), TableError> {
        let writer = self.writer.take().expect("writer is open until commit");
        let file = writer.into_inner().map_err(|source| TableError::Parquet {
            path: self.tmp.clone(),
            source,
        })?;
        file.sync_all().map_err(|source| TableError::Io {
            path: self.tmp.clone(),
            source,
        })?;
        drop(file);
        fs::rename(&self.tmp, &self.dest).map_err(|source| TableError::Io {
            path: self.dest.clone(),
            source,
        })?;
        self.tmp = PathBuf::new();
        Ok(())
    }
}

impl Drop for AtomicTableWriter {
    fn drop(&mut self) {
        // Not committed: remove the partial file. Errors here have nowhere to go.
        if !self.tmp.as_os_str().is_empty() {
            self.writer = None;
            let _ = fs::remove_file(&self.tmp);
        }
    }
}

/// The hidden sibling `dest` is written as before its rename:
/// `.NAME.tmp-PID` ([`temporary_of`] reads it back).
pub fn temporary_path(dest: &Path) -> PathBuf {
    let name = dest
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    dest.with_file_name(format!(".{name}.tmp-{}", std::process::id()))
}

/// The file a hidden temporary was being written as and its writer's pid
/// (`.NAME.tmp-PID` → `(NAME, PID)`), as [`temporary_path`] names them.
pub fn temporary_of(name: &str) -> Option<(&str, &str)> {
    name.strip_prefix('.')?.rsplit_once(".tmp-")
}

/// The file a temporary named `name` was being written as, if its writer is
/// no longer alive on this machine (/proc holds no such pid): a killed
/// writer's leftover.
pub fn orphaned_temporary(name: &str) -> Option<&str> {
    let (table, pid) = temporary_of(name)?;
    (!Path::new("/proc").join(pid).exists()).then_some(table)
}

/// Writes `bytes` to `dest` through a temporary sibling and a rename (for
/// the few outputs that are not Parquet).
pub fn atomic_write(dest: &Path, bytes: &[u8]) -> Result<(), TableError> {
    atomic_write_all(&[(dest, bytes)])
}

/// Writes a set of files that belong together (an engine's job): every one
/// to a temporary sibling first, each synced, then all renamed into place
/// one after the other, so that a failure or a kill while writing leaves
/// the earlier set whole, and only the instants of the renames could mix
/// the two.
pub fn atomic_write_all(files: &[(&Path, &[u8])]) -> Result<(), TableError> {
    use std::io::Write;
    let io_err = |path: &Path, source| TableError::Io {
        path: path.to_path_buf(),
        source,
    };
    let mut temps: Vec<PathBuf> = Vec::new();
    let written = (|| {
        for (dest, bytes) in files {
            if let Some(parent) = dest.parent().filter(|p| !p.as_os_str().is_empty()) {
                fs::create_dir_all(parent).map_err(|e| io_err(dest, e))?;
            }
            let tmp = temporary_path(dest);
            temps.push(tmp.clone());
            (|| {
                let mut f = File::create(&tmp)?;
                f.write_all(bytes)?;
                f.sync_all()
            })()
            .map_err(|e| io_err(dest, e))?;
        }
        for ((dest, _), tmp) in files.iter().zip(&temps) {
            fs::rename(tmp, dest).map_err(|e| io_err(dest, e))?;
        }
        Ok(())
    })();
    if written.is_err() {
        for tmp in &temps {
            let _ = fs::remove_file(tmp);
        }
    }
    written
}

/// A table read back whole: its batches and its key-value metadata.
pub struct TableContents {
    pub batches: Vec<RecordBatch>,
    pub metadata: Vec<(String, String)>,
}

impl TableContents {
    pub fn meta(&self, key: &str) -> Option<&str> {
        self.metadata
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
    }
}

/// The key-value metadata of a Parquet file (its footer only).
pub fn read_metadata(path: &Path) -> Result<Vec<(String, String)>, TableError> {
    Ok(open(path)?.1)
}

/// How many rows a table holds, from its footer.
pub fn row_count(path: &Path) -> Result<usize, TableError> {
    let rows = open(path)?.0.metadata().file_metadata().num_rows();
    Ok(usize::try_from(rows).unwrap_or(0))
}

/// Key-value metadata of a file, as (key, value) pairs.
type KeyValues = Vec<(String, String)>;

/// Opens a Parquet file: its reader builder and its key-value metadata.
fn open(path: &Path) -> Result<(ParquetRecordBatchReaderBuilder<File>, KeyValues), TableError> {
    let file = File::open(path).map_err(|source| TableError::Io {
        path: path.into(),
        source,
    })?;
    let builder =
        ParquetRecordBatchReaderBuilder::try_new(file).map_err(|source| TableError::Parquet {
            path: path.into(),
            source,
        })?;
    let metadata = builder
        .metadata()
        .file_metadata()
        .key_value_metadata()
        .map(|kv| {
            kv.iter()
                .map(|e| (e.key.clone(), e.value.clone().unwrap_or_default()))
                .collect()
        })
        .unwrap_or_default();
    Ok((builder, metadata))
}

/// Reads a whole table, checking that it is `kind` at the schema version
/// this build understands.
pub fn read_table(path: &Path, kind: TableKind) -> Result<TableContents, TableError> {
    let parquet_err = |source| TableError::Parquet {
        path: path.into(),
        source,
    };
    let (builder, metadata) = open(path)?;
    let find = |key: &str| {
        metadata
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.clone())
    };
    let table = find(META_TABLE).unwrap_or_else(|| "(none)".into());
    if table != kind.name {
        return Err(TableError::WrongTable {
            path: path.into(),
            expected: kind.name,
            found: table,
        });
    }
    let version = find(META_SCHEMA_VERSION).unwrap_or_else(|| "(none)".into());
    if version != kind.schema_version.to_string() {
        return Err(TableError::SchemaVersion {
            path: path.into(),
            table: kind.name,
            expected: kind.schema_version,
            found: version,
        });
    }
    let reader = builder
        .with_batch_size(READ_BATCH_ROWS)
        .build()
        .map_err(parquet_err)?;
    let batches = reader
        .collect::<Result<Vec<_>, _>>()
        .map_err(|source| TableError::Arrow {
            path: path.into(),
            source,
        })?;
    Ok(TableContents { batches, metadata })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_set_that_fails_part_way_leaves_the_earlier_set_whole() {
        let dir = std::env::temp_dir().join(format!("rocking-set-{}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        fs::create_dir_all(&dir).unwrap();
        let (a, b) = (dir.join("a.xml"), dir.join("b.csv"));
        atomic_write_all(&[(&a, b"old a"), (&b, b"old b")]).unwrap();
        // The third file cannot be made (its folder is a file): neither of
        // the first two is replaced, and no temporary file is left.
        let blocked = dir.join("b.csv").join("c.ini");
        assert!(atomic_write_all(&[(&a, b"new a"), (&b, b"new b"), (&blocked, b"c")]).is_err());
        assert_eq!(fs::read(&a).unwrap(), b"old a");
        assert_eq!(fs::read(&b).unwrap(), b"old b");
        assert_eq!(fs::read_dir(&dir).unwrap().count(), 2);
        atomic_write_all(&[(&a, b"new a"), (&b, b"new b")]).unwrap();
        assert_eq!(fs::read(&b).unwrap(), b"new b");
        fs::remove_dir_all(&dir).unwrap();
    }
}
