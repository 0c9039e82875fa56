//! The exclusive lock on a run's output folder (`run.lock`).
//!
//! Two runs into one folder (a SLURM requeue while the first task still
//! runs, a second terminal) would both write `outcomes.csv.partial` and
//! `checkpoint.json`. The run that comes second is refused at once, before
//! it touches any file but the lock, with a message naming the holder.
//!
//! The lock is an OS advisory lock (`flock`) on `DIR/run.lock`, which holds
//! the holder's pid, host, start time and command line, and whose
//! modification time the holder refreshes every [`HEARTBEAT`]. The OS lock
//! goes away with the process however it dies (kill -9, scancel, node
//! crash), so a lock file left behind is stale as soon as it can be locked,
//! and is taken over. Where the file system has no working locks (some NFS
//! mounts) the file's contents decide: a holder on this host is alive while
//! its pid is; a holder on another host while its heartbeat is younger than
//! [`STALE_AFTER`].
//!
//! A process may take the lock on a folder it already holds (the command
//! line holds it over the run and what follows it; the run takes it too).

use crate::error::{Error, Result};
use std::collections::HashMap;
use std::fs::{File, OpenOptions};
use std::io::{Read, Seek, Write};
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::mpsc::{Receiver, RecvTimeoutError, Sender, channel};
use std::time::{Duration, SystemTime};

/// The lock file's name inside the output folder.
pub const LOCK: &str = "run.lock";
/// How often the holder refreshes the lock file's modification time.
pub const HEARTBEAT: Duration = Duration::from_secs(20);
/// A holder on another host whose heartbeat is older than this is taken as
/// gone (only where the file system's locks do not work).
pub const STALE_AFTER: Duration = Duration::from_secs(120);

/// Folders this process holds, with how many guards hold each.
static HELD: Mutex<Option<HashMap<PathBuf, usize>>> = Mutex::new(None);

/// The lock on an output folder, held until dropped.
#[derive(Debug)]
pub struct RunLock {
    key: PathBuf,
    inner: Option<Held>,
}

#[derive(Debug)]
struct Held {
    path: PathBuf,
    file: File,
    stop: Option<Sender<()>>,
    heartbeat: Option<std::thread::JoinHandle<()>>,
}

/// Who holds (or held) a lock, as its file says.
#[derive(Clone, Debug, Default, PartialEq)]
struct Holder {
    pid: u32,
    host: String,
    started_unix: u64,
    command: String,
}

impl Holder {
    fn me() -> Holder {
        Holder {
            pid: std::process::id(),
            host: host_name(),
            started_unix: SystemTime::now()
                .duration_since(SystemTime::UNIX_EPOCH)
                .map_or(0, |d| d.as_secs()),
            command: std::env::args().collect::<Vec<_>>().join(" "),
        }
    }

    fn text(&self) -> String {
        format!(
            "pid={}\nhost={}\nstarted_unix={}\ncommand={}\n",
            self.pid,
            self.host,
            self.started_unix,
            self.command.replace('\n', " ")
        )
    }

    fn parse(text: &str) -> Option<Holder> {
        let mut h = Holder::default();
        for line in text.lines() {
            let (k, v) = line.split_once('=')?;
            match k {
                "pid" => h.pid = v.trim().parse().ok()?,
                "host" => h.host = v.trim().to_string(),
                "started_unix" => h.started_unix = v.trim().parse().unwrap_or(0),
                "command" => h.command = v.to_string(),
                _ => {}
            }
        }
        (h.pid != 0 && !h.host.is_empty()).then_some(h)
    }

    fn describe(&self) -> String {
        let since = if self.started_unix > 0 {
            format!(" since {}", super::manifest::iso8601(self.started_unix))
        } else {
            String::new()
        };
        format!(
            "pid {} on host {}{since} ({})",
            self.pid, self.host, self.command
        )
    }
}

/// This machine's host name (`/proc/sys/kernel/hostname`, `/etc/hostname`,
/// `$HOSTNAME`), or `unknown`.
fn host_name() -> String {
    ["/proc/sys/kernel/hostname", "/etc/hostname"]
        .iter()
        .find_map(|p| std::fs::read_to_string(p).ok())
        .or_else(|| std::env::var("HOSTNAME").ok())
        .map(|s| s.trim().to_string())
        .filter(|s| !s.is_empty())
        .unwrap_or_else(|| "unknown".to_string())
}

impl RunLock {
    /// Takes the lock on `dir` (which must exist), or refuses naming the
    /// holder.
    pub fn acquire(dir: &Path) -> Result<RunLock> {
        let key = std::fs::canonicalize(dir).map_err(Error::io(dir))?;
        {
            let mut held = HELD.lock().unwrap_or_else(|e| e.into_inner());
            if let Some(n) = held.get_or_insert_with(HashMap::new).get_mut(&key) {
                *n += 1;
                return Ok(RunLock { key, inner: None });
            }
        }
        let inner = take(&dir.join(LOCK), dir)?;
        let mut held = HELD.lock().unwrap_or_else(|e| e.into_inner());
        held.get_or_insert_with(HashMap::new).insert(key.clone(), 1);
        Ok(RunLock {
            key,
            inner: Some(inner),
        })
    }
}

fn refuse(dir: &Path, path: &Path, holder: Option<&Holder>, why: &str) -> Error {
    let who = holder.map_or_else(|| "another process".to_string(), Holder::describe);
    Error::Conflict {
        path: dir.to_path_buf(),
        message: format!(
            "another run is writing into this folder: {who}{why}; wait for it to end or pass \
             another --out (if it is gone and this persists, delete {})",
            path.display()
        ),
    }
}

/// Opens, locks and claims the lock file at `path`.
fn take(path: &Path, dir: &Path) -> Result<Held> {
    for _ in 0..10 {
        let mut file = OpenOptions::new()
            .read(true)
            .write(true)
            .create(true)
            .truncate(false)
            .open(path)
            .map_err(Error::io(path))?;
        let os_lock = match file.try_lock() {
            Ok(()) => true,
            Err(std::fs::TryLockError::WouldBlock) => {
                let mut text = String::new();
                let _ = file.read_to_string(&mut text);
                return Err(refuse(dir, path, Holder::parse(&text).as_ref(), ""));
            }
            // No working locks here: the file's contents decide.
            Err(std::fs::TryLockError::Error(_)) => false,
        };
        // The holder before us may have removed the file between our open and
        // our lock: then we hold a lock on a name no one else sees. Retry.
        if !same_file(&file, path) {
            continue;
        }
        let mut text = String::new();
        file.read_to_string(&mut text).map_err(Error::io(path))?;
        if let Some(old) = Holder::parse(&text) {
            let me = host_name();
            let alive = if old.host == me {
                // Our OS lock proves the holder dead (it would hold it); else
                // ask /proc, and assume alive if it cannot be known.
                !os_lock
                    && old.pid != std::process::id()
                    && crate::io_util::pid_alive(old.pid).unwrap_or(true)
            } else {
                let age = std::fs::metadata(path)
                    .and_then(|m| m.modified())
                    .ok()
                    .and_then(|t| SystemTime::now().duration_since(t).ok())
                    .unwrap_or(Duration::ZERO);
                !os_lock && age < STALE_AFTER
            };
            if alive {
                let why = if old.host == me {
                    ", which is alive".to_string()
                } else {
                    format!(
                        ", whose heartbeat is less than {} s old",
                        STALE_AFTER.as_secs()
                    )
                };
                return Err(refuse(dir, path, Some(&old), &why));
            }
        }
        let me = Holder::me();
        file.set_len(0).map_err(Error::io(path))?;
        file.rewind().map_err(Error::io(path))?;
        file.write_all(me.text().as_bytes())
            .map_err(Error::io(path))?;
        file.sync_data().map_err(Error::io(path))?;
        let (stop, stopped) = channel();
        let heartbeat = file
            .try_clone()
            .ok()
            .map(|f| std::thread::spawn(move || beat(f, stopped)));
        return Ok(Held {
            path: path.to_path_buf(),
            file,
            stop: Some(stop),
            heartbeat,
        });
    }
    Err(Error::Conflict {
        path: dir.to_path_buf(),
        message: format!("could not take {}: it keeps being replaced", path.display()),
    })
}

/// Whether the open `file` is the file now at `path`.
fn same_file(file: &File, path: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        match (file.metadata(), std::fs::metadata(path)) {
            (Ok(a), Ok(b)) => a.ino() == b.ino() && a.dev() == b.dev(),
            _ => false,
        }
    }
    #[cfg(not(unix))]
    {
        let _ = file;
        path.exists()
    }
}

/// Refreshes the lock file's modification time every [`HEARTBEAT`] until
/// the sender of `stop` is dropped.
fn beat(file: File, stop: Receiver<()>) {
    while let Err(RecvTimeoutError::Timeout) = stop.recv_timeout(HEARTBEAT) {
        let _ = file.set_modified(SystemTime::now());
    }
}

impl Drop for RunLock {
    fn drop(&mut self) {
        let mut held = HELD.lock().unwrap_or_else(|e| e.into_inner());
        let map = held.get_or_insert_with(HashMap::new);
        if let Some(n) = map.get_mut(&self.key) {
            *n -= 1;
            if *n > 0 && self.inner.is_none() {
                return;
            }
        }
        if let Some(mut inner) = self.inner.take() {
            map.remove(&self.key);
            drop(inner.stop.take());
            if let Some(h) = inner.heartbeat.take() {
                let _ = h.join();
            }
            // Remove the file while still holding the OS lock; a process
            // that opened it meanwhile sees it is gone and retries.
            let _ = std::fs::remove_file(&inner.path);
            let _ = inner.file.unlock();
        }
    }
}
