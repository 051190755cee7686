//! Writing files so that a crash, a full disk or an interrupt never leaves a half-written
//! output: each file goes to a temporary beside it and is renamed into place, alone or
//! with a group ([`Staging`]).

use std::fs;
use std::io::Write as _;
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};

use super::{io_error, IoError};

static TEMP_COUNTER: AtomicUsize = AtomicUsize::new(0);

/// The temporary files of the writes under way, so that an interrupted run can remove
/// them ([`abandon_writes`]).
static IN_FLIGHT: std::sync::Mutex<Vec<std::path::PathBuf>> = std::sync::Mutex::new(Vec::new());

fn in_flight() -> std::sync::MutexGuard<'static, Vec<std::path::PathBuf>> {
    IN_FLIGHT.lock().unwrap_or_else(|e| e.into_inner())
}

/// Removes the temporary files of the writes under way and keeps any other write from
/// starting: for a handler of SIGINT or SIGTERM that then exits, so that an interrupted
/// run leaves every output either as it was or complete, and no temporary behind.
pub fn abandon_writes() {
    let mut writes = in_flight();
    for tmp in writes.drain(..) {
        let _ = fs::remove_file(tmp);
    }
    // The lock stays taken until the process exits: no new temporary can appear.
    std::mem::forget(writes);
}

thread_local! {
    /// The writes of the current staging: (temporary, final path), renamed on commit.
    static STAGED: std::cell::RefCell<Option<Vec<(std::path::PathBuf, std::path::PathBuf)>>> =
        const { std::cell::RefCell::new(None) };
}

/// A group of outputs that appear together or not at all. While a `Staging` is alive on
/// this thread, [`write_atomic`] leaves each complete, synced file under its temporary
/// name; [`Staging::commit`] renames them all into place. If any write fails, or the
/// staging is dropped without a commit (an error returned early), every temporary is
/// removed and no output of the group appears. FIFOs and devices are written at once.
#[derive(Debug)]
pub struct Staging {
    _private: (),
}

impl Staging {
    /// Starts staging the writes of this thread.
    pub fn begin() -> Staging {
        STAGED.with(|st| *st.borrow_mut() = Some(Vec::new()));
        Staging { _private: () }
    }

    /// Renames every staged file into place.
    pub fn commit(self) -> Result<(), IoError> {
        let staged = STAGED.with(|st| st.borrow_mut().take()).unwrap_or_default();
        let mut result = Ok(());
        for (tmp, path) in &staged {
            if result.is_ok() {
                result = fs::rename(tmp, path).map_err(|e| {
                    io_error(path, format!("cannot rename {} onto it", tmp.display()), e)
                });
            }
            if result.is_err() {
                let _ = fs::remove_file(tmp);
            }
            in_flight().retain(|t| t != tmp);
        }
        result
    }
}

impl Drop for Staging {
    fn drop(&mut self) {
        if let Some(staged) = STAGED.with(|st| st.borrow_mut().take()) {
            for (tmp, _) in staged {
                let _ = fs::remove_file(&tmp);
                in_flight().retain(|t| *t != tmp);
            }
        }
    }
}

/// The longest file name an output may have: its temporary name `.{name}.tmp-{pid}-{k}`
/// must still fit the usual 255-byte limit of a directory entry.
pub const MAX_OUTPUT_NAME: usize = 255 - 32;

/// Checks, before any work is done, that `path` can take an output: its directory
/// exists, its name is not too long, and what is there (links followed) is a regular
/// file, a FIFO or a character device, or nothing yet. `what` names the option.
pub fn check_output(path: &Path) -> Result<(), IoError> {
    // A link is checked where the write will go (a dangling link's directory too).
    if let Some(target) = link_target(path)? {
        return check_output(&target);
    }
    let refuse = |why: &str| io_error(path, "cannot write", std::io::Error::other(why.to_string()));
    let name = path
        .file_name()
        .ok_or_else(|| refuse("it names a directory; expected a file name"))?;
    if name.len() > MAX_OUTPUT_NAME {
        return Err(refuse(&format!(
            "a file name of {} bytes; at most {MAX_OUTPUT_NAME} are accepted",
            name.len()
        )));
    }
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    if !dir.is_dir() {
        return Err(refuse(&format!(
            "the directory {} does not exist",
            dir.display()
        )));
    }
    // A directory may exist and refuse new files (read-only, full quota): try one.
    let probe = dir.join(format!(".stillpoint-probe-{}", std::process::id()));
    match fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&probe)
    {
        Ok(_) => {
            let _ = fs::remove_file(&probe);
        }
        Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {}
        Err(e) => {
            return Err(refuse(&format!(
                "no file can be created in {} ({e})",
                dir.display()
            )))
        }
    }
    #[cfg(unix)]
    if let Ok(meta) = fs::metadata(path) {
        use std::os::unix::fs::FileTypeExt;
        let kind = meta.file_type();
        if !(kind.is_file() || kind.is_fifo() || kind.is_char_device()) {
            return Err(refuse(
                "it is a directory, socket or block device; expected a file name",
            ));
        }
    }
    Ok(())
}

/// Where a write to `path` goes when `path` is a symbolic link (`None` when it is not):
/// the file the link leads to, replaced next to it so that the link stays; a dangling
/// link is followed by hand to where the file will be. Refuses a chain of links that does
/// not end in a file.
fn link_target(path: &Path) -> Result<Option<std::path::PathBuf>, IoError> {
    if !fs::symlink_metadata(path).is_ok_and(|m| m.file_type().is_symlink()) {
        return Ok(None);
    }
    let target = match fs::canonicalize(path) {
        Ok(t) => t,
        Err(_) => {
            let link =
                fs::read_link(path).map_err(|e| io_error(path, "cannot read the link", e))?;
            path.parent().unwrap_or(Path::new(".")).join(link)
        }
    };
    if fs::symlink_metadata(&target).is_ok_and(|m| m.file_type().is_symlink()) {
        return Err(io_error(
            path,
            "cannot write",
            std::io::Error::other("a chain of links that does not end in a file"),
        ));
    }
    Ok(Some(target))
}

/// Removes `.{name}.tmp-{pid}-{k}` files in `dir` whose process no longer runs: what a
/// killed write of this output left behind. Best effort: a file that cannot be removed
/// is left.
fn remove_stale_temporaries(dir: &Path, name: &std::ffi::OsStr) {
    let prefix = format!(".{}.tmp-", name.to_string_lossy());
    let Ok(entries) = fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let file_name = entry.file_name();
        let file_name = file_name.to_string_lossy();
        let Some(rest) = file_name.strip_prefix(&prefix) else {
            continue;
        };
        let Some(pid) = rest.split('-').next().and_then(|p| p.parse::<u32>().ok()) else {
            continue;
        };
        let alive = pid == std::process::id() || Path::new(&format!("/proc/{pid}")).exists();
        if !alive && entry.file_type().is_ok_and(|t| t.is_file()) {
            let _ = fs::remove_file(entry.path());
        }
    }
}

/// Replaces `path` with `bytes` so that readers see either the old file or the complete
/// new one: the bytes go to `.{name}.tmp-{pid}-{k}` in the same directory, are synced to
/// disk and renamed over `path`. On any failure the temporary file is removed and `path`
/// is left as it was. An existing file's permissions are kept.
///
/// What is at `path` decides how: a symbolic link is written through (its final target is
/// replaced atomically, the link stays); a FIFO or a character device (`/dev/stdout`) is
/// streamed to directly, since it cannot be replaced; a directory, socket or block device
/// is refused. Temporaries that an earlier run of a killed process left for this output
/// are removed.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), IoError> {
    write_atomic_with(path, &|w: &mut dyn std::io::Write| w.write_all(bytes))
}

/// [`write_atomic`] with the bytes written by `write` (called once), through a buffer.
pub(crate) fn write_atomic_with(
    path: &Path,
    write: &dyn Fn(&mut dyn std::io::Write) -> std::io::Result<()>,
) -> Result<(), IoError> {
    let name = path.file_name().ok_or_else(|| {
        io_error(
            path,
            "cannot write",
            std::io::Error::new(std::io::ErrorKind::InvalidInput, "not a file name"),
        )
    })?;
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        // What the path leads to (links followed) decides whether it can be replaced.
        if let Ok(meta) = fs::metadata(path) {
            let kind = meta.file_type();
            if kind.is_fifo() || kind.is_char_device() {
                let mut f = fs::OpenOptions::new()
                    .write(true)
                    .open(path)
                    .map_err(|e| io_error(path, "cannot open", e))?;
                let mut buffered = std::io::BufWriter::new(&mut f);
                return write(&mut buffered)
                    .and_then(|()| buffered.flush())
                    .map_err(|e| io_error(path, "cannot write", e));
            }
            if !kind.is_file() {
                return Err(io_error(
                    path,
                    "cannot write",
                    std::io::Error::other(
                        "it is a directory, socket or block device; expected a file name",
                    ),
                ));
            }
        }
        if let Some(target) = link_target(path)? {
            return write_atomic_with(&target, write);
        }
    }
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };

    remove_stale_temporaries(dir, name);
    // Registered while the lock is held, so that an interrupt sees every temporary.
    let mut writes = in_flight();
    let (tmp, mut file) = loop {
        let k = TEMP_COUNTER.fetch_add(1, Ordering::Relaxed);
        let mut tmp_name = std::ffi::OsString::from(".");
        tmp_name.push(name);
        tmp_name.push(format!(".tmp-{}-{k}", std::process::id()));
        let tmp = dir.join(tmp_name);
        // create_new: never truncate or follow something that is already there.
        match fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&tmp)
        {
            Ok(file) => {
                writes.push(tmp.clone());
                break (tmp, file);
            }
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists && k < 1 << 20 => continue,
            Err(e) => {
                return Err(io_error(
                    path,
                    format!("cannot create temporary file {}", tmp.display()),
                    e,
                ))
            }
        }
    };

    drop(writes);
    let written = (|| {
        let mut buffered = std::io::BufWriter::new(&mut file);
        write(&mut buffered)
            .and_then(|()| buffered.flush())
            .map_err(|e| io_error(path, format!("cannot write {}", tmp.display()), e))?;
        drop(buffered);
        file.flush()
            .and_then(|()| file.sync_all())
            .map_err(|e| io_error(path, format!("cannot sync {}", tmp.display()), e))?;
        if let Ok(old) = fs::metadata(path) {
            if old.is_file() {
                let _ = file.set_permissions(old.permissions());
            }
        }
        drop(file);
        // Under a staging, the rename waits for its commit.
        let staged = STAGED.with(|st| match st.borrow_mut().as_mut() {
            Some(list) => {
                list.push((tmp.clone(), path.to_path_buf()));
                true
            }
            None => false,
        });
        if staged {
            return Ok(true);
        }
        fs::rename(&tmp, path)
            .map_err(|e| io_error(path, format!("cannot rename {} onto it", tmp.display()), e))
            .map(|()| false)
    })();

    if written.is_err() {
        let _ = fs::remove_file(&tmp);
    }
    if written.as_ref().is_ok_and(|staged| *staged) {
        return Ok(());
    }
    in_flight().retain(|t| *t != tmp);
    written?;
    // The rename is durable only once the directory entry is; best effort, since some
    // platforms and file systems cannot sync a directory.
    #[cfg(unix)]
    if let Ok(d) = fs::File::open(dir) {
        let _ = d.sync_all();
    }
    Ok(())
}
