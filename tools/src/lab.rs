//! cloth-lab's supervisor: the three processes as children in one domain, their logs
//! forwarded with a prefix, restarts on request (a key on the terminal, or
//! `cloth-lab restart ROLE` through a Unix socket in the domain's directory), and a clean
//! shutdown (SIGTERM, then SIGKILL after a grace period).
//!
//! Failure policy: haptic-loop or cloth-sim exiting with an error stops the lab, which
//! then exits non-zero. cloth-ui is hot-swappable: when it exits the others keep running
//! and the lab says how to start it again; a failed UI still makes the lab's exit code
//! non-zero unless a restarted UI replaced it.

use std::io::{BufRead, BufReader, Write};
use std::os::unix::net::{UnixListener, UnixStream};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use shared::domain::Domain;

/// The supervised processes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Role {
    Haptic,
    Sim,
    Ui,
}

impl Role {
    pub const ALL: [Role; 3] = [Role::Haptic, Role::Sim, Role::Ui];

    pub fn parse(s: &str) -> Result<Self, String> {
        match s {
            "haptic" | "haptic-loop" | "h" => Ok(Self::Haptic),
            "sim" | "cloth-sim" | "s" => Ok(Self::Sim),
            "ui" | "cloth-ui" | "u" => Ok(Self::Ui),
            _ => Err(format!("unknown process '{s}' (haptic, sim or ui)")),
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Self::Haptic => "haptic",
            Self::Sim => "sim",
            Self::Ui => "ui",
        }
    }

    pub fn binary(self) -> &'static str {
        match self {
            Self::Haptic => "haptic-loop",
            Self::Sim => "cloth-sim",
            Self::Ui => "cloth-ui",
        }
    }
}

/// The launcher's control socket for `domain`, in the domain's private directory (made
/// when missing).
pub fn socket_path(domain: &Domain) -> Result<PathBuf, String> {
    Ok(domain
        .root_dir()
        .map_err(|e| e.to_string())?
        .join("cloth-lab.sock"))
}

/// Sends one request line to a running launcher and returns its one-line reply.
pub fn request(domain: &Domain, line: &str) -> Result<String, String> {
    // Asking makes nothing: a domain with no cloth-lab keeps no directory.
    let path = domain
        .root_path()
        .map_err(|e| e.to_string())?
        .join("cloth-lab.sock");
    let mut s = UnixStream::connect(&path).map_err(|e| {
        format!(
            "no cloth-lab is running in domain '{}' ({}: {e})",
            domain.name(),
            path.display()
        )
    })?;
    s.set_read_timeout(Some(Duration::from_secs(30)))
        .map_err(|e| e.to_string())?;
    writeln!(s, "{line}").map_err(|e| e.to_string())?;
    let mut reply = String::new();
    BufReader::new(s)
        .read_line(&mut reply)
        .map_err(|e| format!("no reply from cloth-lab: {e}"))?;
    Ok(reply.trim_end().to_string())
}

/// Where the other binaries are: next to this one.
pub fn sibling(name: &str) -> Result<PathBuf, String> {
    let exe = std::env::current_exe().map_err(|e| e.to_string())?;
    let dir = exe.parent().ok_or("the launcher has no directory")?;
    Ok(dir.join(name))
}

/// A request to the supervisor from the socket or the terminal; the reply goes back on
/// `reply` when there is one.
pub struct Request {
    pub line: String,
    pub reply: Option<mpsc::Sender<String>>,
}

struct Slot {
    role: Role,
    args: Vec<String>,
    /// Given on the first start only (cloth-sim's `--fresh`: a restart must resume the
    /// design being worked on, not start another).
    first: Vec<String>,
    child: Option<Child>,
    starts: u32,
    /// Set while the lab itself stops or restarts it: its exit is expected.
    stopping: bool,
    failed: Option<String>,
    /// The last error line the process printed (its reason, when it fails).
    last_error: std::sync::Arc<std::sync::Mutex<Option<String>>>,
}

impl Slot {
    /// The arguments of its next start.
    fn args_now(&self) -> impl Iterator<Item = &String> {
        let first = if self.starts == 0 {
            &self.first[..]
        } else {
            &[]
        };
        self.args.iter().chain(first)
    }
}

pub struct Supervisor {
    slots: Vec<Slot>,
    domain: Domain,
    listener: Option<UnixListener>,
    requests: mpsc::Receiver<Request>,
    req_tx: mpsc::Sender<Request>,
    pub grace: Duration,
}

/// Prints a child's output with its role as prefix; remembers its last error line.
fn forward(
    role: Role,
    pipe: impl std::io::Read + Send + 'static,
    last_error: std::sync::Arc<std::sync::Mutex<Option<String>>>,
) {
    std::thread::spawn(move || {
        for line in BufReader::new(pipe).lines() {
            match line {
                Ok(l) => {
                    if l.contains("error:")
                        && let Ok(mut e) = last_error.lock()
                    {
                        *e = Some(l.clone());
                    }
                    eprintln!("[{:<6}] {l}", role.name());
                }
                Err(_) => break,
            }
        }
    });
}

/// SIGTERM to a child not yet reaped (so its pid is still ours).
fn sigterm(child: &Child) {
    let pid = rustix::process::Pid::from_child(child);
    let _ = rustix::process::kill_process(pid, rustix::process::Signal::TERM);
}

fn describe(s: ExitStatus) -> String {
    use std::os::unix::process::ExitStatusExt;
    match (s.code(), s.signal()) {
        (Some(c), _) => format!("exit code {c}"),
        (None, Some(sig)) => format!("signal {sig}"),
        _ => "unknown status".into(),
    }
}

impl Supervisor {
    /// A supervisor for `domain` with its control socket open (refused when another
    /// launcher is live in the domain).
    pub fn new(domain: Domain) -> Result<Self, String> {
        let path = socket_path(&domain)?;
        if UnixStream::connect(&path).is_ok() {
            return Err(format!(
                "a cloth-lab is already running in domain '{}'; use another --domain or `cloth-lab restart`",
                domain.name()
            ));
        }
        let _ = std::fs::remove_file(&path);
        let listener = UnixListener::bind(&path).map_err(|e| format!("{}: {e}", path.display()))?;
        // The directory is the user's alone already; the socket is too.
        std::fs::set_permissions(&path, std::os::unix::fs::PermissionsExt::from_mode(0o600))
            .map_err(|e| format!("{}: {e}", path.display()))?;
        listener.set_nonblocking(true).map_err(|e| e.to_string())?;
        let (req_tx, requests) = mpsc::channel();
        Ok(Self {
            slots: Vec::new(),
            domain,
            listener: Some(listener),
            requests,
            req_tx,
            grace: Duration::from_secs(5),
        })
    }

    /// Requests typed on the terminal: `h`, `s`, `u` restart a process, `q` quits.
    pub fn read_terminal(&self) {
        let tx = self.req_tx.clone();
        std::thread::spawn(move || {
            for line in std::io::stdin().lock().lines() {
                let Ok(l) = line else { break };
                let l = l.trim().to_string();
                let line = match l.as_str() {
                    "" => continue,
                    "q" | "quit" => "stop".to_string(),
                    "?" | "help" => "help".to_string(),
                    r if Role::parse(r).is_ok() => format!("restart {r}"),
                    other => other.to_string(),
                };
                if tx.send(Request { line, reply: None }).is_err() {
                    break;
                }
            }
        });
    }

    pub fn add(&mut self, role: Role, args: Vec<String>) {
        self.add_first(role, args, Vec::new());
    }

    /// [`Supervisor::add`], with `first` added to the arguments of the first start only.
    pub fn add_first(&mut self, role: Role, args: Vec<String>, first: Vec<String>) {
        self.slots.push(Slot {
            role,
            args,
            first,
            child: None,
            starts: 0,
            stopping: false,
            failed: None,
            last_error: Default::default(),
        });
    }

    pub fn has(&self, role: Role) -> bool {
        self.slots.iter().any(|s| s.role == role)
    }

    fn slot(&mut self, role: Role) -> Option<&mut Slot> {
        self.slots.iter_mut().find(|s| s.role == role)
    }

    fn spawn(slot: &mut Slot) -> Result<(), String> {
        let bin = sibling(slot.role.binary())?;
        if !bin.is_file() {
            return Err(format!(
                "{} is not built next to cloth-lab ({}); build the workspace first: cargo build --release",
                slot.role.binary(),
                bin.display()
            ));
        }
        let mut c = Command::new(&bin);
        c.args(slot.args_now())
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped());
        let mut child = c
            .spawn()
            .map_err(|e| format!("starting {}: {e}", bin.display()))?;
        if let Ok(mut e) = slot.last_error.lock() {
            *e = None;
        }
        if let Some(o) = child.stdout.take() {
            forward(slot.role, o, slot.last_error.clone());
        }
        if let Some(e) = child.stderr.take() {
            forward(slot.role, e, slot.last_error.clone());
        }
        eprintln!(
            "cloth-lab: started {} (pid {})",
            slot.role.binary(),
            child.id()
        );
        slot.child = Some(child);
        slot.starts += 1;
        slot.stopping = false;
        Ok(())
    }

    /// Starts every process, in the order they were added.
    pub fn start_all(&mut self) -> Result<(), String> {
        for s in &mut self.slots {
            Self::spawn(s)?;
        }
        Ok(())
    }

    fn terminate(child: &mut Child, grace: Duration) -> Option<ExitStatus> {
        // SIGTERM first: every Saiho process shuts down cleanly on it.
        sigterm(child);
        let until = Instant::now() + grace;
        while Instant::now() < until {
            if let Ok(Some(s)) = child.try_wait() {
                return Some(s);
            }
            std::thread::sleep(Duration::from_millis(10));
        }
        let _ = child.kill();
        child.wait().ok()
    }

    /// Stops and starts one process; the others are not touched.
    pub fn restart(&mut self, role: Role) -> Result<String, String> {
        let grace = self.grace;
        let Some(slot) = self.slot(role) else {
            return Err(format!("{} is not part of this lab", role.binary()));
        };
        if let Some(mut c) = slot.child.take() {
            slot.stopping = true;
            let st = Self::terminate(&mut c, grace);
            eprintln!(
                "cloth-lab: stopped {} ({})",
                role.binary(),
                st.map_or("unknown".into(), describe)
            );
        }
        slot.failed = None;
        Self::spawn(slot)?;
        let pid = slot.child.as_ref().map_or(0, |c| c.id());
        Ok(format!("restarted {} (pid {pid})", role.binary()))
    }

    pub fn status(&self) -> String {
        self.slots
            .iter()
            .map(|s| {
                format!(
                    "{}: {} (started {}x)",
                    s.role.binary(),
                    match (&s.child, &s.failed) {
                        (Some(c), _) => format!("running, pid {}", c.id()),
                        (None, Some(f)) => format!("stopped: {f}"),
                        (None, None) => "stopped".into(),
                    },
                    s.starts
                )
            })
            .collect::<Vec<_>>()
            .join("; ")
    }

    /// Stops everything: SIGTERM to all, then SIGKILL to what is left after the grace.
    pub fn stop_all(&mut self) {
        for s in &mut self.slots {
            if let Some(c) = &s.child {
                s.stopping = true;
                sigterm(c);
            }
        }
        let until = Instant::now() + self.grace;
        for s in &mut self.slots {
            if let Some(mut c) = s.child.take() {
                let left = until.saturating_duration_since(Instant::now());
                let st = Self::terminate(&mut c, left);
                eprintln!(
                    "cloth-lab: {} stopped ({})",
                    s.role.binary(),
                    st.map_or("unknown".into(), describe)
                );
            }
        }
    }

    fn accept(&mut self) {
        let Some(l) = &self.listener else { return };
        while let Ok((stream, _)) = l.accept() {
            let tx = self.req_tx.clone();
            std::thread::spawn(move || {
                let _ = stream.set_nonblocking(false);
                let _ = stream.set_read_timeout(Some(Duration::from_secs(5)));
                let mut line = String::new();
                let mut r = BufReader::new(&stream);
                if r.read_line(&mut line).is_err() {
                    return;
                }
                let (rtx, rrx) = mpsc::channel();
                if tx
                    .send(Request {
                        line: line.trim().to_string(),
                        reply: Some(rtx),
                    })
                    .is_err()
                {
                    return;
                }
                if let Ok(reply) = rrx.recv_timeout(Duration::from_secs(30)) {
                    let mut w = &stream;
                    let _ = writeln!(w, "{reply}");
                }
            });
        }
    }

    /// One request; returns whether the lab should stop.
    fn handle(&mut self, req: Request) -> bool {
        let mut words = req.line.split_whitespace();
        let (reply, stop) = match (words.next(), words.next()) {
            (Some("restart"), Some(r)) => match Role::parse(r).and_then(|r| self.restart(r)) {
                Ok(m) => (format!("ok {m}"), false),
                Err(e) => (format!("error {e}"), false),
            },
            (Some("status"), None) => (format!("ok {}", self.status()), false),
            (Some("stop"), None) => ("ok stopping".to_string(), true),
            (Some("help"), None) => (
                "ok keys: h / s / u restart haptic-loop / cloth-sim / cloth-ui, q quits; \
                 `cloth-lab restart ROLE` and `cloth-lab status` from another terminal"
                    .to_string(),
                false,
            ),
            _ => (
                format!(
                    "error unknown request '{}' (restart haptic|sim|ui, status, stop)",
                    req.line
                ),
                false,
            ),
        };
        match req.reply {
            Some(tx) => {
                let _ = tx.send(reply);
            }
            None => eprintln!("cloth-lab: {reply}"),
        }
        stop
    }

    /// Supervises until `stop`, a stop request, `until`, or a fatal child failure.
    /// Returns the failures (empty: a clean run).
    pub fn supervise(&mut self, stop: &dyn Fn() -> bool, until: Option<Instant>) -> Vec<String> {
        let mut fatal = false;
        while !stop() && until.is_none_or(|u| Instant::now() < u) {
            self.accept();
            let mut quit = false;
            while let Ok(r) = self.requests.try_recv() {
                quit |= self.handle(r);
            }
            if quit {
                break;
            }
            for s in &mut self.slots {
                let Some(c) = &mut s.child else { continue };
                let Ok(Some(st)) = c.try_wait() else { continue };
                s.child = None;
                if s.stopping {
                    continue;
                }
                let ok = st.success();
                if !ok {
                    // Its pipes close as it exits: give the forwarders a moment to read the
                    // last line, its reason.
                    std::thread::sleep(Duration::from_millis(50));
                    let why = s.last_error.lock().ok().and_then(|e| e.clone());
                    s.failed = Some(match why {
                        Some(w) => format!("{}: {w}", describe(st)),
                        None => describe(st),
                    });
                }
                match s.role {
                    Role::Ui => eprintln!(
                        "cloth-lab: cloth-ui exited ({}); haptic-loop and cloth-sim keep running. Press u or run `cloth-lab restart ui --domain {}` to start it again",
                        describe(st),
                        self.domain.name()
                    ),
                    _ => {
                        eprintln!(
                            "cloth-lab: {} exited ({}); stopping the lab",
                            s.role.binary(),
                            describe(st)
                        );
                        fatal = true;
                    }
                }
            }
            if fatal {
                break;
            }
            std::thread::sleep(Duration::from_millis(20));
        }
        self.stop_all();
        self.slots
            .iter()
            .filter_map(|s| {
                s.failed
                    .as_ref()
                    .map(|f| format!("{} failed ({f})", s.role.binary()))
            })
            .collect()
    }
}

impl Drop for Supervisor {
    fn drop(&mut self) {
        for s in &mut self.slots {
            if let Some(c) = &mut s.child {
                let _ = c.kill();
                let _ = c.wait();
            }
        }
        if self.listener.take().is_some()
            && let Ok(path) = socket_path(&self.domain)
        {
            let _ = std::fs::remove_file(path);
        }
        // The children are gone: what they left in /dev/shm and the domain's directory
        // goes too (unless a process of the domain started outside cloth-lab still runs).
        shared::services::release(&self.domain);
    }
}

/// Whether a display is there for a window.
pub fn have_display() -> bool {
    ["DISPLAY", "WAYLAND_DISPLAY"]
        .iter()
        .any(|v| std::env::var_os(v).is_some_and(|s| !s.is_empty()))
}

/// Whether `path` exists as a file.
pub fn exists(path: &Path) -> bool {
    path.is_file()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `--fresh` goes with cloth-sim's first start only: a restart (the s key, `cloth-lab
    /// restart sim`, or after a crash) resumes the design being worked on. With it on
    /// every start, the fixed `--fresh` would set that design aside each time.
    #[test]
    fn first_start_arguments_are_not_given_again() {
        let mut slot = Slot {
            role: Role::Sim,
            args: vec!["run".into()],
            first: vec!["--fresh".into()],
            child: None,
            starts: 0,
            stopping: false,
            failed: None,
            last_error: Default::default(),
        };
        let now = |s: &Slot| s.args_now().cloned().collect::<Vec<_>>();
        assert_eq!(now(&slot), ["run", "--fresh"]);
        slot.starts = 1;
        assert_eq!(now(&slot), ["run"]);
    }
}
