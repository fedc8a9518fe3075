//! Opening a file a user named for reading, whatever it turns out to be.
//!
//! A regular file is opened. A FIFO (a named pipe, `/dev/stdin` from a
//! pipe, `<(...)`) is opened once something writes to it, within a wait
//! (with no writer, open() blocks for ever and the process no longer
//! answers SIGTERM's handler), or refused when the caller wants files
//! only. A folder, a device (`/dev/zero`, a terminal) or a socket is
//! refused: reading one would fail, block or never end.
//!
//! Every file the front ends read on a user's word (model files, input
//! tables, mesh files) goes through [`open`] or [`read`], so that none of
//! them can hang the command.

use std::fs::File;
use std::io::{self, Read};
use std::path::Path;
use std::time::Duration;

/// How long a FIFO may wait for the program that writes to it, unless the
/// caller says otherwise.
pub const FIFO_WAIT: Duration = Duration::from_secs(5);

/// What to do with a FIFO.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Fifo {
    /// Open it once something writes to it, within this wait.
    Wait(Duration),
    /// Refuse it as not a regular file.
    Refuse,
}

/// What a path names when it is not a regular file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    Folder,
    Device,
    Fifo,
    Socket,
    Other,
}

impl Kind {
    /// The kind of what `meta` describes, `None` for a regular file.
    pub fn of(meta: &std::fs::Metadata) -> Option<Kind> {
        if meta.is_file() {
            return None;
        }
        if meta.is_dir() {
            return Some(Kind::Folder);
        }
        #[cfg(unix)]
        {
            use std::os::unix::fs::FileTypeExt;
            let ty = meta.file_type();
            if ty.is_char_device() || ty.is_block_device() {
                return Some(Kind::Device);
            }
            if ty.is_fifo() {
                return Some(Kind::Fifo);
            }
            if ty.is_socket() {
                return Some(Kind::Socket);
            }
        }
        Some(Kind::Other)
    }

    /// "a folder", "a device", "a FIFO (named pipe)", "a socket", "a special file".
    pub fn describe(self) -> &'static str {
        match self {
            Kind::Folder => "a folder",
            Kind::Device => "a device",
            Kind::Fifo => "a FIFO (named pipe)",
            Kind::Socket => "a socket",
            Kind::Other => "a special file",
        }
    }
}

/// Why a file was not opened or read.
#[derive(Debug)]
pub enum OpenError {
    /// The system's error (no such file, no permission, ...).
    Io(io::Error),
    /// The path names something other than a regular file (or a FIFO, when
    /// FIFOs are read).
    NotAFile(Kind),
    /// A FIFO nothing wrote to within the wait.
    NoWriter { waited: Duration },
    /// More bytes than the caller reads: the file's size when known
    /// (nothing was read then), else what a FIFO gave before it was left.
    TooLarge { size: Option<u64>, limit: u64 },
}

impl OpenError {
    /// The system's error, if that is what it is.
    pub fn io_kind(&self) -> Option<io::ErrorKind> {
        match self {
            OpenError::Io(e) => Some(e.kind()),
            _ => None,
        }
    }
}

/// An opened file, and its size when it is a regular file.
#[derive(Debug)]
pub struct Opened {
    pub file: File,
    /// `None` for a FIFO.
    pub size: Option<u64>,
}

/// Opens `path` for reading; see the module's documentation.
pub fn open(path: &Path, fifo: Fifo) -> Result<Opened, OpenError> {
    let meta = std::fs::metadata(path).map_err(OpenError::Io)?;
    match Kind::of(&meta) {
        None => {
            let file = File::open(path).map_err(OpenError::Io)?;
            // The name may have been replaced since: what was opened counts.
            let meta = file.metadata().map_err(OpenError::Io)?;
            match Kind::of(&meta) {
                None => Ok(Opened { file, size: Some(meta.len()) }),
                Some(kind) => Err(OpenError::NotAFile(kind)),
            }
        }
        Some(Kind::Fifo) => match fifo {
            Fifo::Wait(wait) => open_fifo(path, wait).map(|file| Opened { file, size: None }),
            Fifo::Refuse => Err(OpenError::NotAFile(Kind::Fifo)),
        },
        Some(kind) => Err(OpenError::NotAFile(kind)),
    }
}

/// The bytes of `path`, at most `limit` of them: a regular file larger
/// than that is refused before anything is read.
pub fn read(path: &Path, fifo: Fifo, limit: u64) -> Result<Vec<u8>, OpenError> {
    let Opened { file, size } = open(path, fifo)?;
    if let Some(size) = size.filter(|&s| s > limit) {
        return Err(OpenError::TooLarge { size: Some(size), limit });
    }
    let mut bytes = Vec::with_capacity(size.unwrap_or(0) as usize);
    file.take(limit.saturating_add(1)).read_to_end(&mut bytes).map_err(OpenError::Io)?;
    if bytes.len() as u64 > limit {
        // A file that grew while read, or a FIFO that gives more.
        return Err(OpenError::TooLarge { size: None, limit });
    }
    Ok(bytes)
}

/// Opens a FIFO on a thread of its own, so that a FIFO nobody writes to is
/// given up after `wait` instead of blocking for ever.
fn open_fifo(path: &Path, wait: Duration) -> Result<File, OpenError> {
    let (opened, opened_here) = std::sync::mpsc::channel();
    let opening = path.to_path_buf();
    std::thread::spawn(move || {
        let _ = opened.send(File::open(&opening));
    });
    match opened_here.recv_timeout(wait) {
        // The thread stays blocked in open(); it ends with the process.
        Err(_) => Err(OpenError::NoWriter { waited: wait }),
        Ok(file) => file.map_err(OpenError::Io),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("multibody-files-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[test]
    fn regular_files_read_within_their_limit() {
        let dir = scratch("regular");
        let file = dir.join("a.txt");
        std::fs::write(&file, "hello").unwrap();
        assert_eq!(read(&file, Fifo::Refuse, 5).unwrap(), b"hello");
        assert!(matches!(read(&file, Fifo::Refuse, 4), Err(OpenError::TooLarge { size: Some(5), limit: 4 })));
        assert!(matches!(read(&dir, Fifo::Refuse, 4), Err(OpenError::NotAFile(Kind::Folder))));
        let missing = read(&dir.join("no.txt"), Fifo::Refuse, 4).unwrap_err();
        assert_eq!(missing.io_kind(), Some(io::ErrorKind::NotFound));
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[cfg(unix)]
    #[test]
    fn fifos_are_refused_or_given_up_and_devices_refused() {
        let dir = scratch("fifo");
        let fifo = dir.join("pipe");
        let made = std::process::Command::new("mkfifo").arg(&fifo).status();
        if !made.is_ok_and(|s| s.success()) {
            return; // no mkfifo here
        }
        assert!(matches!(open(&fifo, Fifo::Refuse), Err(OpenError::NotAFile(Kind::Fifo))));
        let waited = Duration::from_millis(50);
        assert!(matches!(open(&fifo, Fifo::Wait(waited)), Err(OpenError::NoWriter { .. })));
        // Another FIFO: the thread left waiting on the first would take its writer.
        let fifo = dir.join("written");
        assert!(std::process::Command::new("mkfifo").arg(&fifo).status().unwrap().success());
        let writing = fifo.clone();
        let writer = std::thread::spawn(move || std::fs::write(writing, "through a pipe"));
        assert_eq!(read(&fifo, Fifo::Wait(Duration::from_secs(60)), 100).unwrap(), b"through a pipe");
        writer.join().unwrap().unwrap();
        assert!(matches!(open(Path::new("/dev/zero"), Fifo::Refuse), Err(OpenError::NotAFile(Kind::Device))));
        let _ = std::fs::remove_dir_all(&dir);
    }
}
