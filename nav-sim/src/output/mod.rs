//! Output files of the `nav-sim` commands, written so that a failure destroys nothing.
//!
//! An [`OutputFile`] is written into a temporary file beside its target (same directory, so
//! the same file system) and renamed over the target by [`OutputFile::commit`]: a run that
//! fails, or is killed, leaves no half-written file and never truncates an existing one.
//! Creating it up front also proves the target writable before a long run starts.
//! [`refuse_inputs`] refuses an output that is one of the command's inputs before anything is
//! opened for writing, and [`prepare_directory`] checks an output directory the same way.
//! Every error names its path. The calibration table, its CSVs and plots are [`report`]; the
//! measured tables the documentation includes are [`results`].

pub mod report;
pub mod results;
pub mod scenario_label;

use std::fs::{File, Metadata};
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

use tempfile::NamedTempFile;

/// Why an output could not be written.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// The output is one of the command's inputs (the same path, a link to it or the same
    /// file through a hard link).
    #[error("refusing to write {}: it is the input {}", output.display(), input.display())]
    SameAsInput {
        /// The output path.
        output: PathBuf,
        /// The input it would overwrite.
        input: PathBuf,
    },
    /// A file is to be written where a directory exists.
    #[error("cannot create {}: it is a directory, a file is expected", path.display())]
    IsDirectory {
        /// The path.
        path: PathBuf,
    },
    /// A directory is expected where something else exists.
    #[error("cannot use {} as the output directory: it exists and is not a directory", path.display())]
    NotDirectory {
        /// The path.
        path: PathBuf,
    },
    /// An I/O error on `path`.
    #[error("cannot {action} {}: {source}", path.display())]
    Io {
        /// What was being done: `create`, `write`, `replace`, `create directory`, ...
        action: &'static str,
        /// The path.
        path: PathBuf,
        /// The I/O error.
        source: io::Error,
    },
}

impl OutputError {
    fn io<'a>(action: &'static str, path: &'a Path) -> impl FnOnce(io::Error) -> Self + 'a {
        move |source| Self::Io {
            action,
            path: path.to_path_buf(),
            source,
        }
    }
}

/// `error` without the ` at path "<temporary file>"` that tempfile appends to its message:
/// the messages name the target, not the temporary file's random name.
fn without_temporary_path(error: io::Error) -> io::Error {
    let message = error.to_string();
    match message.rsplit_once(" at path ") {
        Some((head, _)) => io::Error::new(error.kind(), head),
        None => error,
    }
}

/// Where the bytes go until the commit.
#[derive(Debug)]
enum Sink {
    /// A temporary file beside the target, renamed over it by the commit; registered for
    /// [`remove_staged_files`] while it lives.
    Staged(BufWriter<NamedTempFile>, Registration),
    /// A target that is not a regular file (a device or a FIFO such as `/dev/null`), written
    /// in place: renaming over it would replace the device node.
    Direct(BufWriter<File>),
}

/// The temporary files of the [`OutputFile`]s not yet committed or dropped: what
/// [`remove_staged_files`] removes when the process is interrupted.
static STAGED_FILES: std::sync::Mutex<Vec<PathBuf>> = std::sync::Mutex::new(Vec::new());

/// The registry of staged files, even if a thread panicked while holding it (a list of paths
/// cannot be left inconsistent by a push or a retain).
fn staged_files() -> std::sync::MutexGuard<'static, Vec<PathBuf>> {
    STAGED_FILES
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// A temporary file's entry in the registry of [`remove_staged_files`], removed when dropped
/// (after the commit's rename, or with the temporary file).
#[derive(Debug)]
struct Registration(PathBuf);

impl Registration {
    fn new(path: &Path) -> Self {
        staged_files().push(path.to_path_buf());
        Self(path.to_path_buf())
    }
}

impl Drop for Registration {
    fn drop(&mut self) {
        staged_files().retain(|path| *path != self.0);
    }
}

/// Removes the temporary files of every [`OutputFile`] not yet committed, and returns how many
/// it removed: for a signal handler (SIGINT, SIGTERM) that ends the process, where no `Drop`
/// runs. The targets are left as they were.
///
/// # Examples
/// ```
/// let directory = tempfile::tempdir().unwrap();
/// let path = directory.path().join("log.csv");
/// let staged = nav_sim::output::OutputFile::create(&path).unwrap();
/// assert_eq!(nav_sim::output::remove_staged_files(), 1);
/// assert!(!staged.staging_path().exists() && !path.exists());
/// ```
pub fn remove_staged_files() -> usize {
    let mut files = staged_files();
    let removed = files
        .drain(..)
        .filter(|path| std::fs::remove_file(path).is_ok())
        .count();
    removed
}

/// An output file written to a temporary file in its directory and renamed over the target by
/// [`commit`](Self::commit); dropped without a commit, it leaves the target as it was. The
/// temporary file is also removed by [`remove_staged_files`] (an interrupted command).
///
/// Write errors name the target path.
#[derive(Debug)]
pub struct OutputFile {
    /// The target as the user gave it (for messages).
    path: PathBuf,
    /// The file the commit replaces: the target, resolved through symbolic links so that a
    /// link is written through rather than replaced.
    target: PathBuf,
    sink: Sink,
}

impl OutputFile {
    /// Creates the temporary file for `path` in `path`'s directory. The temporary file keeps
    /// the target's extension, so writers that choose a format from it (the plotting
    /// library's PNG encoder) see the right one.
    ///
    /// # Errors
    /// [`OutputError::IsDirectory`] if `path` is a directory; [`OutputError::Io`] naming
    /// `path` if its directory does not exist, is not a directory or is not writable.
    pub fn create(path: &Path) -> Result<Self, OutputError> {
        let create_error = OutputError::io("create", path);
        let target = match std::fs::metadata(path) {
            Ok(metadata) if metadata.is_dir() => {
                return Err(OutputError::IsDirectory {
                    path: path.to_path_buf(),
                })
            }
            Ok(metadata) if !metadata.is_file() => {
                let file = std::fs::OpenOptions::new()
                    .write(true)
                    .open(path)
                    .map_err(create_error)?;
                return Ok(Self {
                    path: path.to_path_buf(),
                    target: path.to_path_buf(),
                    sink: Sink::Direct(BufWriter::new(file)),
                });
            }
            Ok(_) => std::fs::canonicalize(path).map_err(create_error)?,
            Err(error) if error.kind() == io::ErrorKind::NotFound => path.to_path_buf(),
            Err(error) => return Err(create_error(error)),
        };
        let name = target.file_name().ok_or_else(|| OutputError::Io {
            action: "create",
            path: path.to_path_buf(),
            source: io::Error::new(io::ErrorKind::InvalidInput, "the path names no file"),
        })?;
        let directory = match target.parent() {
            Some(parent) if !parent.as_os_str().is_empty() => parent,
            _ => Path::new("."),
        };
        let suffix = match target.extension() {
            Some(extension) => format!(".tmp.{}", extension.to_string_lossy()),
            None => ".tmp".to_string(),
        };
        let prefix = format!(".{}.", name.to_string_lossy());
        let mut builder = tempfile::Builder::new();
        builder.prefix(&prefix).suffix(&suffix);
        // The default of the temporary file (owner only) would become the output's mode; the
        // usual mode of a new file (0666 less the umask) is what a plain create gives.
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            builder.permissions(std::fs::Permissions::from_mode(0o666));
        }
        let file = builder
            .tempfile_in(directory)
            .map_err(|error| OutputError::io("create", path)(without_temporary_path(error)))?;
        let registration = Registration::new(file.path());
        Ok(Self {
            path: path.to_path_buf(),
            target,
            sink: Sink::Staged(BufWriter::new(file), registration),
        })
    }

    /// [`refuse_inputs`] then [`create`](Self::create): the output file of a command that
    /// reads `inputs`.
    ///
    /// # Errors
    /// [`OutputError::SameAsInput`] before anything is created, or as
    /// [`create`](Self::create).
    pub fn create_distinct(path: &Path, inputs: &[&Path]) -> Result<Self, OutputError> {
        refuse_inputs(path, inputs)?;
        Self::create(path)
    }

    /// The target path, as given to [`create`](Self::create).
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The file the bytes go to until the commit, for writers that take a path rather than a
    /// [`Write`] (the plotting library): the temporary file, or the target itself when it is
    /// a device or FIFO.
    pub fn staging_path(&self) -> &Path {
        match &self.sink {
            Sink::Staged(file, _) => file.get_ref().path(),
            Sink::Direct(_) => &self.target,
        }
    }

    /// Flushes the output to disk and renames it over the target.
    ///
    /// # Errors
    /// [`OutputError::Io`] naming the target if the flush or the rename fails; the temporary
    /// file is then removed and the target left as it was.
    pub fn commit(self) -> Result<PathBuf, OutputError> {
        let path = self.path;
        match self.sink {
            Sink::Staged(writer, _registration) => {
                let file = writer
                    .into_inner()
                    .map_err(|error| OutputError::io("write", &path)(error.into_error()))?;
                file.as_file()
                    .sync_all()
                    .map_err(OutputError::io("write", &path))?;
                file.persist(&self.target)
                    .map_err(|error| OutputError::io("replace", &path)(error.error))?;
            }
            Sink::Direct(mut writer) => writer.flush().map_err(OutputError::io("write", &path))?,
        }
        Ok(path)
    }

    fn writer(&mut self) -> &mut dyn Write {
        match &mut self.sink {
            Sink::Staged(writer, _) => writer,
            Sink::Direct(writer) => writer,
        }
    }

    /// The I/O error `error` of a write, naming the target.
    fn named(&self, error: io::Error) -> io::Error {
        io::Error::new(
            error.kind(),
            format!("cannot write {}: {error}", self.path.display()),
        )
    }
}

impl Write for OutputFile {
    fn write(&mut self, buffer: &[u8]) -> io::Result<usize> {
        self.writer()
            .write(buffer)
            .map_err(|error| self.named(error))
    }

    fn flush(&mut self) -> io::Result<()> {
        self.writer().flush().map_err(|error| self.named(error))
    }
}

/// Whether two existing paths are the same file: the same canonical path, or (on Unix) the
/// same device and inode, which also catches hard links.
fn same_file(a: &Path, a_metadata: &Metadata, b: &Path, b_metadata: &Metadata) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        if a_metadata.dev() == b_metadata.dev() && a_metadata.ino() == b_metadata.ino() {
            return true;
        }
    }
    #[cfg(not(unix))]
    let _ = (a_metadata, b_metadata);
    matches!(
        (std::fs::canonicalize(a), std::fs::canonicalize(b)),
        (Ok(a), Ok(b)) if a == b
    )
}

/// Refuses `output` if it is one of `inputs`. An output that does not exist yet is no input;
/// an input that does not exist is skipped (reading it fails on its own, naming it).
///
/// # Errors
/// [`OutputError::SameAsInput`] naming both paths.
pub fn refuse_inputs(output: &Path, inputs: &[&Path]) -> Result<(), OutputError> {
    let Ok(output_metadata) = std::fs::metadata(output) else {
        return Ok(());
    };
    for input in inputs {
        let Ok(input_metadata) = std::fs::metadata(input) else {
            continue;
        };
        if same_file(output, &output_metadata, input, &input_metadata) {
            return Err(OutputError::SameAsInput {
                output: output.to_path_buf(),
                input: input.to_path_buf(),
            });
        }
    }
    Ok(())
}

/// Makes `path` ready to receive output files: creates it (and its parents) if missing, and
/// proves it writable by creating and removing a temporary file in it.
///
/// # Errors
/// [`OutputError::NotDirectory`] if `path` exists and is not a directory; [`OutputError::Io`]
/// naming `path` if it cannot be created (e.g. a parent is a file) or written into.
pub fn prepare_directory(path: &Path) -> Result<(), OutputError> {
    match std::fs::metadata(path) {
        Ok(metadata) if metadata.is_dir() => {}
        Ok(_) => {
            return Err(OutputError::NotDirectory {
                path: path.to_path_buf(),
            })
        }
        Err(error) if error.kind() == io::ErrorKind::NotFound => {
            std::fs::create_dir_all(path).map_err(OutputError::io("create directory", path))?;
        }
        Err(error) => return Err(OutputError::io("create directory", path)(error)),
    }
    tempfile::Builder::new()
        .prefix(".nav-sim-probe.")
        .tempfile_in(path)
        .map(drop)
        .map_err(|error| {
            OutputError::io("write into directory", path)(without_temporary_path(error))
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// How many entries `directory` holds (a temporary file left behind would count).
    fn entries(directory: &Path) -> usize {
        std::fs::read_dir(directory).unwrap().count()
    }

    #[test]
    fn the_target_changes_only_on_commit() {
        let directory = tempfile::tempdir().unwrap();
        let path = directory.path().join("out.csv");
        std::fs::write(&path, "old\n").unwrap();
        let mut output = OutputFile::create(&path).unwrap();
        assert!(output
            .staging_path()
            .to_string_lossy()
            .ends_with(".tmp.csv"));
        output.write_all(b"new\n").unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "old\n");
        drop(output);
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "old\n");
        assert_eq!(entries(directory.path()), 1);

        let mut output = OutputFile::create(&path).unwrap();
        output.write_all(b"new\n").unwrap();
        assert_eq!(output.commit().unwrap(), path);
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "new\n");
        assert_eq!(entries(directory.path()), 1);
    }

    #[cfg(unix)]
    #[test]
    fn a_symbolic_link_is_written_through_and_a_device_in_place() {
        let directory = tempfile::tempdir().unwrap();
        let real = directory.path().join("real.csv");
        let link = directory.path().join("link.csv");
        std::fs::write(&real, "old\n").unwrap();
        std::os::unix::fs::symlink(&real, &link).unwrap();
        let mut output = OutputFile::create(&link).unwrap();
        output.write_all(b"new\n").unwrap();
        output.commit().unwrap();
        assert!(std::fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink());
        assert_eq!(std::fs::read_to_string(&real).unwrap(), "new\n");

        let mut null = OutputFile::create(Path::new("/dev/null")).unwrap();
        null.write_all(b"nothing\n").unwrap();
        null.commit().unwrap();
        use std::os::unix::fs::FileTypeExt;
        assert!(std::fs::metadata("/dev/null")
            .unwrap()
            .file_type()
            .is_char_device());
    }

    #[test]
    fn bad_targets_are_named() {
        let directory = tempfile::tempdir().unwrap();
        let file = directory.path().join("file");
        std::fs::write(&file, "x").unwrap();
        let cases = [
            directory.path().to_path_buf(),
            directory.path().join("missing").join("out.csv"),
            file.join("out.csv"),
        ];
        for path in cases {
            let message = OutputFile::create(&path).unwrap_err().to_string();
            assert!(message.contains(&path.display().to_string()), "{message}");
        }
        let message = prepare_directory(&file).unwrap_err().to_string();
        assert!(message.contains(&file.display().to_string()), "{message}");
        let nested = file.join("plots");
        let message = prepare_directory(&nested).unwrap_err().to_string();
        assert!(message.contains(&nested.display().to_string()), "{message}");
        prepare_directory(&directory.path().join("new").join("plots")).unwrap();
        assert_eq!(entries(&directory.path().join("new").join("plots")), 0);
    }

    #[test]
    fn inputs_are_refused_by_path_link_and_hard_link() {
        let directory = tempfile::tempdir().unwrap();
        let input = directory.path().join("log.csv");
        std::fs::write(&input, "log\n").unwrap();
        let other = directory.path().join("other.csv");
        std::fs::write(&other, "other\n").unwrap();
        let dotted = directory.path().join(".").join("log.csv");
        let hard = directory.path().join("hard.csv");
        std::fs::hard_link(&input, &hard).unwrap();
        for output in [&input, &dotted, &hard] {
            assert!(matches!(
                refuse_inputs(output, &[&other, &input]),
                Err(OutputError::SameAsInput { .. })
            ));
        }
        refuse_inputs(&other, &[&input]).unwrap();
        refuse_inputs(&directory.path().join("new.csv"), &[&input]).unwrap();
        assert_eq!(std::fs::read_to_string(&input).unwrap(), "log\n");
    }
}
