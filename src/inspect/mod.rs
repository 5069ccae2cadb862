//! The Rerun inspector: sink choice and what each command records.
//!
//! The physics never imports this module: commands compute their results first, then hand them to
//! a recorder here. Conventions of every recording:
//! * lengths in **mm** (the unit engineers read profiles in), angles in rad unless the entity
//!   name says otherwise;
//! * cross-sections are stored in track coordinates (Y to the left, Z up) as points
//!   `[Y, −Z]`, because Rerun's 2D views are Y-down: the picture is the cross-section seen
//!   from ahead of the vehicle (left rail on the right of the screen), and hovering shows Y in mm
//!   and the depth below the top-of-rail plane;
//! * the wall-clock `log_time` timeline is disabled, so recordings of the same input are
//!   reproducible;
//! * every recording carries a blueprint (its layout is chosen here, not guessed by the viewer).
//!
//! The `.rrd` file footer is written only when every handle of the stream is dropped; commands
//! keep the stream in a local so that early returns (errors) still drop it and flush the file.

pub mod assessment;
pub mod bands;
pub mod compare;
pub mod contact;
pub mod creep;
pub mod design;
pub mod kec;
pub mod layout;
pub mod paper;
pub mod patch;
pub mod precision;
pub mod profiles;
pub mod readback;
pub mod rrd_file;
pub mod run;
pub mod study;
pub mod track;
pub mod world3d;
pub mod xyplot;

use std::path::PathBuf;

use rerun::{Color, RecordingStream, Scalars, SeriesLines, TimeColumn};

pub use layout::{Container, Item, Layout, View};

/// Where a recording goes.
#[derive(Debug, Clone, PartialEq)]
pub enum Sink {
    /// Write an `.rrd` file.
    Save(PathBuf),
    /// Start a viewer (`rerun` on PATH) and stream to it; falls back to saving `kecsim.rrd`.
    Spawn,
    /// Stream to a running viewer at this gRPC URL.
    Connect(String),
    /// Stream to a running viewer at this gRPC URL and save the same recording to the file
    /// (`--connect` or `--spawn` with `--save`); the file is written whole whatever the viewer
    /// does.
    ConnectAndSave(String, PathBuf, FileCopy),
}

impl Sink {
    /// The file the recording is saved to, if it is saved.
    pub fn saved(&self) -> Option<&std::path::Path> {
        match self {
            Sink::Save(p) | Sink::ConnectAndSave(_, p, _) => Some(p),
            Sink::Spawn | Sink::Connect(_) => None,
        }
    }
}

/// The file of a [`Sink::ConnectAndSave`] once the recording is open (its end is written by
/// [`finish_recording`] on its own, not when the viewer's stream ends).
#[derive(Debug, Clone, Default)]
pub struct FileCopy(std::sync::Arc<std::sync::OnceLock<rrd_file::Handle>>);

impl PartialEq for FileCopy {
    /// Every copy is alike: a sink is compared by where it goes.
    fn eq(&self, _: &FileCopy) -> bool {
        true
    }
}

/// Default file of `--save`.
pub const DEFAULT_RRD: &str = "kecsim.rrd";
/// Default gRPC URL of `--connect`.
pub const DEFAULT_CONNECT_URL: &str = "rerun+http://127.0.0.1:9876/proxy";

/// Inspector errors.
#[derive(Debug, thiserror::Error)]
pub enum InspectError {
    #[error("cannot open the recording ({what}): {source}")]
    Open {
        what: String,
        #[source]
        source: rerun::RecordingStreamError,
    },
    /// A model evaluation needed for the recording failed.
    #[error("{0}")]
    Model(String),
    #[error("cannot log {entity}: {source}")]
    Log {
        entity: String,
        #[source]
        source: rerun::RecordingStreamError,
    },
}

/// How long `--connect` waits for a viewer to answer.
pub const VIEWER_TIMEOUT: std::time::Duration = std::time::Duration::from_secs(3);

/// How long `--spawn` waits for the viewer it started to listen ([`spawn_viewer`]);
/// `KECSIM_VIEWER_WAIT_S` sets another.
pub const SPAWN_WAIT: std::time::Duration = std::time::Duration::from_secs(10);

/// Why a spawned viewer could not show anything here, if it could not: no `rerun` executable on
/// PATH, or (Linux) no display for its window (`DISPLAY`, `WAYLAND_DISPLAY` unset: a server, a
/// container, an ssh session without forwarding).
pub fn spawn_obstacle() -> Option<String> {
    if !viewer_on_path() {
        return Some("no Rerun viewer (`rerun`) on PATH to spawn".into());
    }
    if cfg!(target_os = "linux")
        && std::env::var_os("DISPLAY").is_none()
        && std::env::var_os("WAYLAND_DISPLAY").is_none()
        && std::env::var_os("WAYLAND_SOCKET").is_none()
    {
        return Some("no display for a spawned viewer (DISPLAY and WAYLAND_DISPLAY are unset)".into());
    }
    None
}

/// Whether a `rerun` executable is on PATH (what `--spawn` starts).
pub fn viewer_on_path() -> bool {
    std::env::var_os("PATH").is_some_and(|paths| {
        std::env::split_paths(&paths).any(|d| {
            let p = d.join("rerun");
            p.is_file() || p.with_extension("exe").is_file()
        })
    })
}

/// Starts a Rerun viewer (`rerun` on PATH) and returns the URL to stream to once it listens
/// (within [`SPAWN_WAIT`], or `KECSIM_VIEWER_WAIT_S`); the error says why not — a `rerun` that
/// cannot run, or one that never listens, is then a fallback decided before any output is
/// guarded, never a wait without end.
pub fn spawn_viewer() -> Result<String, String> {
    spawn_viewer_until(&|| false)
}

/// [`spawn_viewer`], ending its waits as soon as `stop()` (a Ctrl-C or SIGTERM the command
/// caught) — the error then says so. Every wait is bounded: `rerun --version`, the SDK's start
/// of the viewer (which asks `rerun --version` again and reads its output to the end, without a
/// bound: a `rerun` whose background process keeps that output open held a run for minutes; run
/// on a thread of its own here, let go when the wait is over) and the wait for it to listen.
pub fn spawn_viewer_until(stop: &dyn Fn() -> bool) -> Result<String, String> {
    use std::time::Duration;
    let opts = rerun::SpawnOptions {
        // The SDK's own wait (~6 s, not settable) is replaced by ours.
        wait_for_bind: false,
        ..Default::default()
    };
    let wait = crate::files::wait_from_env("KECSIM_VIEWER_WAIT_S", SPAWN_WAIT);
    let start = std::time::Instant::now();
    let stopped = || "stopped while waiting for the spawned Rerun viewer".to_string();
    // The SDK asks the executable for its version first and waits for the answer without end: a
    // `rerun` that hangs would hang the command. Asked here first, within the wait.
    viewer_answers(wait, stop)?;
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let _ = tx.send(rerun::spawn(&opts));
    });
    let info = loop {
        match rx.recv_timeout(Duration::from_millis(50)) {
            Ok(started) => break started.map_err(|e| format!("cannot spawn a Rerun viewer ({e})"))?,
            Err(std::sync::mpsc::RecvTimeoutError::Timeout) => {
                if stop() {
                    return Err(stopped());
                }
                if start.elapsed() >= wait {
                    return Err(format!(
                        "the Rerun viewer on PATH did not start within {:.0} s (its `rerun --version` keeps its output open)",
                        wait.as_secs_f64()
                    ));
                }
            }
            Err(std::sync::mpsc::RecvTimeoutError::Disconnected) => {
                return Err(
                    "the Rerun viewer's start failed (the SDK's thread ended without an answer)".into(),
                )
            }
        }
    };
    let url = format!("rerun+http://127.0.0.1:{}/proxy", info.port);
    loop {
        if stop() {
            return Err(stopped());
        }
        match probe_viewer(&url, Duration::from_millis(500)) {
            Ok(()) => return Ok(url),
            Err(_) if start.elapsed() < wait => std::thread::sleep(Duration::from_millis(100)),
            Err(_) => {
                return Err(format!(
                    "the spawned Rerun viewer does not listen at {url} within {:.0} s",
                    wait.as_secs_f64()
                ))
            }
        }
    }
}

/// Whether `rerun --version` (the `rerun` on PATH) answers within `wait`; one that does not is
/// killed and the error says so.
fn viewer_answers(wait: std::time::Duration, stop: &dyn Fn() -> bool) -> Result<(), String> {
    use std::process::{Command, Stdio};
    let mut child = Command::new("rerun")
        .arg("--version")
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .map_err(|e| format!("cannot run the Rerun viewer `rerun` ({e})"))?;
    let start = std::time::Instant::now();
    loop {
        match child.try_wait() {
            Ok(Some(_)) => return Ok(()),
            Ok(None) if stop() => {
                child.kill().ok();
                child.wait().ok();
                return Err("stopped while waiting for the Rerun viewer's `rerun --version`".into());
            }
            Ok(None) if start.elapsed() < wait => std::thread::sleep(std::time::Duration::from_millis(20)),
            _ => {
                child.kill().ok();
                child.wait().ok();
                return Err(format!(
                    "the Rerun viewer on PATH does not answer `rerun --version` within {:.0} s",
                    wait.as_secs_f64()
                ));
            }
        }
    }
}

/// Checks that something listens at the viewer URL's host and port (`rerun+http://HOST:PORT/…`;
/// port 9876 when none is given) within `timeout`; the error says what was tried.
pub fn probe_viewer(url: &str, timeout: std::time::Duration) -> Result<(), String> {
    use std::net::{TcpStream, ToSocketAddrs};
    let rest = url.split_once("://").map_or(url, |(_, r)| r);
    let authority = rest.split('/').next().unwrap_or("");
    let hostport = if authority
        .rsplit_once(':')
        .is_some_and(|(_, p)| p.parse::<u16>().is_ok())
    {
        authority.to_string()
    } else {
        format!("{authority}:9876")
    };
    let addrs: Vec<_> = hostport
        .to_socket_addrs()
        .map_err(|e| format!("cannot resolve the viewer address {hostport} of {url}: {e}"))?
        .collect();
    for a in &addrs {
        if TcpStream::connect_timeout(a, timeout).is_ok() {
            return Ok(());
        }
    }
    Err(format!(
        "no Rerun viewer answers at {url} (tried {hostport} for {:.0} s; start one with `rerun`)",
        timeout.as_secs_f64()
    ))
}

/// Ends a recording: a file is renamed from its part file into place (see [`crate::files`]); a
/// stream to a viewer is delivered ([`deliver`]: everything taken by the other side, within
/// [`delivery_timeout`]); the line to print says where the recording went. A stream the viewer
/// refused is an error (the command then exits non-zero, after writing its other outputs) unless
/// the recording was also saved; one whose end the viewer did not confirm in time is said in the
/// line, not an error (what it took it shows). `rec` must be the stream's last handle: a file's
/// footer is written when it drops here.
pub fn finish_recording(rec: RecordingStream, sink: &Sink) -> Result<String, String> {
    match sink {
        Sink::Save(p) => {
            let flushed = rec.flush_blocking().map_err(|e| e.to_string());
            drop(rec);
            complete_file(p, flushed)
        }
        Sink::ConnectAndSave(url, p, copy) => {
            // Both sinks flushed; the file's own errors are its handle's.
            let (delivery, file_end) = end_stream(rec, || {
                copy.0.get().map_or_else(
                    || Err("the file was never opened".to_string()),
                    rrd_file::Handle::finish,
                )
            });
            let saved = complete_file(p, file_end)?;
            let line = match delivery {
                Ok(()) => format!("streamed to {url}"),
                Err(Delivery::Unconfirmed(e)) => format!(
                    "streamed to {url} (its end not confirmed: {e}; what the viewer shows may lack the last samples)"
                ),
                Err(Delivery::Refused(e)) => format!("the viewer at {url} did NOT take the recording ({e})"),
            };
            Ok(format!("{saved}; {line}"))
        }
        Sink::Spawn | Sink::Connect(_) => {
            let (to, viewer) = match sink {
                Sink::Connect(u) => (u.clone(), format!("the viewer at {u}")),
                _ => ("the spawned viewer".to_string(), "the spawned viewer".to_string()),
            };
            match end_stream(rec, || ()).0 {
                Ok(()) => Ok(format!("streamed to {to}")),
                Err(Delivery::Unconfirmed(e)) => Ok(format!(
                    "streamed to {to}; its end was not confirmed ({e}): what the viewer shows may lack the last samples (--save FILE keeps a copy)"
                )),
                Err(Delivery::Refused(e)) => Err(format!(
                    "the recording was NOT delivered: {viewer} did not take it ({e}); run again with --save FILE"
                )),
            }
        }
    }
}

/// The end of a stream: flushed within the delivery wait ([`delivery_timeout`]), `after_flush`
/// run (a saved copy's end), then the stream let go on a thread of its own in any case — dropped
/// here, a stream to a silent viewer would wait without end — waited for only when the flush went
/// through. Returns the delivery and what `after_flush` returned.
fn end_stream<T>(rec: RecordingStream, after_flush: impl FnOnce() -> T) -> (Result<(), Delivery>, T) {
    let timeout = delivery_timeout();
    let start = std::time::Instant::now();
    let streamed = rec.flush_with_timeout(timeout).map_err(Delivery::from);
    let after = after_flush();
    let left = match &streamed {
        Ok(()) => timeout.saturating_sub(start.elapsed()),
        Err(_) => std::time::Duration::ZERO,
    };
    let delivered = deliver(rec, left);
    (streamed.and(delivered), after)
}

/// The end of a saved recording: `flushed` (every write's first error, the footer's included)
/// checked, the part file checked whole, synced and renamed onto the target; a stream (a FIFO,
/// a device) is written in place. The line to print, or why the file was not saved (the file
/// there before is kept).
fn complete_file(p: &std::path::Path, flushed: Result<(), String>) -> Result<String, String> {
    let target = crate::files::write_target(p);
    let stream = crate::files::output_kind(p) == Ok(crate::files::OutputKind::Stream);
    let part = crate::files::part_path(&target);
    let fail = |e: String| {
        if !stream {
            std::fs::remove_file(&part).ok();
        }
        format!(
            "cannot save {}: {e}{}",
            p.display(),
            if stream {
                ""
            } else {
                "; the file there before is kept"
            }
        )
    };
    // Every write error of the recording is seen here (rrd_file keeps the first and fails every
    // flush after it); the footer is checked on the file itself.
    flushed.map_err(&fail)?;
    if stream {
        return Ok(format!("saved {}", p.display()));
    }
    check_rrd_whole(&part).map_err(&fail)?;
    std::fs::File::open(&part)
        .and_then(|f| f.sync_all())
        .map_err(|e| fail(e.to_string()))?;
    // Now whole, it takes the file's name (through a symlink: the file it points to).
    std::fs::rename(&part, &target).map_err(|e| fail(e.to_string()))?;
    Ok(format!("saved {}", p.display()))
}

/// Checks that the recording file `path` ends with the stream footer the SDK writes last (`RRF2`
/// `FOOT`, one entry whose footer payload ends where the 32-byte stream footer begins): a file cut
/// short by a full disk does not.
fn check_rrd_whole(path: &std::path::Path) -> Result<(), String> {
    use std::io::{Read, Seek, SeekFrom};
    const STREAM_FOOTER: u64 = 32;
    let mut f = std::fs::File::open(path).map_err(|e| e.to_string())?;
    let len = f.metadata().map_err(|e| e.to_string())?.len();
    let cut = || {
        format!(
            "the recording was cut short ({len} bytes written, no end of stream): the disk is full or failed"
        )
    };
    if len < STREAM_FOOTER {
        return Err(cut());
    }
    let mut tail = [0u8; STREAM_FOOTER as usize];
    f.seek(SeekFrom::End(-(STREAM_FOOTER as i64)))
        .and_then(|_| f.read_exact(&mut tail))
        .map_err(|e| e.to_string())?;
    let word = |a: usize| u64::from_le_bytes(tail[a..a + 8].try_into().unwrap_or([0; 8]));
    let (start, span) = (word(0), word(8));
    let whole = &tail[20..28] == b"RRF2FOOT"
        && tail[28..32] == 1u32.to_le_bytes()
        && start.checked_add(span) == Some(len - STREAM_FOOTER);
    if whole {
        Ok(())
    } else {
        Err(cut())
    }
}

/// How long the end of a streamed recording may take to reach the viewer or the server: the
/// stream's queue sent and the call closed by the other side (see [`deliver`]).
pub const DELIVERY_TIMEOUT: std::time::Duration = std::time::Duration::from_secs(20);

/// [`DELIVERY_TIMEOUT`], or the seconds of `KECSIM_DELIVERY_WAIT_S`.
pub fn delivery_timeout() -> std::time::Duration {
    crate::files::wait_from_env("KECSIM_DELIVERY_WAIT_S", DELIVERY_TIMEOUT)
}

/// Why a stream's delivery is not confirmed.
#[derive(Debug, Clone, PartialEq)]
pub enum Delivery {
    /// The other side refused the stream or failed (nothing, or not all, arrived).
    Refused(String),
    /// The stream went out but its end was not confirmed in time (a slow or busy viewer: what
    /// was sent may well have arrived).
    Unconfirmed(String),
}

impl From<rerun::sink::SinkFlushError> for Delivery {
    fn from(e: rerun::sink::SinkFlushError) -> Delivery {
        match e {
            rerun::sink::SinkFlushError::Timeout => Delivery::Unconfirmed(e.to_string()),
            _ => Delivery::Refused(e.to_string()),
        }
    }
}

/// Ends a stream to a viewer or a server and waits, at most `timeout`, until the other side has
/// taken everything: the SDK's flush only hands the queued messages to its network task (a
/// process that exits then loses the last of them in flight: the summary, the last rows), while
/// dropping the stream's last handle sends what is queued, ends the call and waits for the other
/// side to close it — the confirmation. That wait has no end in the SDK (a viewer that stopped
/// answering), so the drop runs on a thread of its own, waited for with `timeout`; past it the
/// stream is left to the process's exit ([`Delivery::Unconfirmed`]).
pub fn deliver(rec: RecordingStream, timeout: std::time::Duration) -> Result<(), Delivery> {
    let (done, confirmed) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        drop(rec);
        let _ = done.send(());
    });
    confirmed.recv_timeout(timeout).map_err(|_| {
        Delivery::Unconfirmed(format!(
            "the end of the stream was not confirmed within {:.0} s",
            timeout.as_secs_f64()
        ))
    })
}

/// Opens a recording stream on `sink` with the layout `layout()` builds (see [`layout`]). A
/// `Spawn` that cannot start a viewer falls back to saving [`DEFAULT_RRD`] and says so on stderr.
pub fn open_recording(
    app_id: &'static str,
    sink: &Sink,
    layout: impl Fn() -> Layout,
) -> Result<RecordingStream, InspectError> {
    open_recording_with(app_id, sink, layout).map(|(rec, _)| rec)
}

/// The file a recording is saved to: its part file beside the target (renamed onto it by
/// [`finish_recording`]: a reader never sees half a recording, one that fails keeps the old
/// file), or a stream (`/dev/stdout`, a named pipe: its reader waited for, at most
/// [`crate::files::stream_wait`]).
fn open_rrd_file(path: &std::path::Path) -> Result<std::fs::File, InspectError> {
    let open_failed =
        |e: String| InspectError::Model(format!("cannot save the recording to {}: {e}", path.display()));
    if crate::files::output_kind(path) == Ok(crate::files::OutputKind::Stream) {
        crate::files::open_stream(path).map_err(|e| open_failed(e.to_string()))
    } else {
        let target = crate::files::write_target(path);
        crate::files::create_side_file(&crate::files::part_path(&target))
            .map_err(|e| open_failed(e.to_string()))
    }
}

/// [`open_recording`], also returning the layout as sent (to change it later).
pub fn open_recording_with(
    app_id: &'static str,
    sink: &Sink,
    layout: impl Fn() -> Layout,
) -> Result<(RecordingStream, layout::SentLayout), InspectError> {
    let builder = || rerun::RecordingStreamBuilder::new(app_id);
    let rec = match sink {
        // Written to the part file beside the target, renamed onto it by finish_recording: a
        // reader never sees half a recording, and a recording that fails keeps the old file.
        // The recording is encoded by kecsim's own sink (rrd_file: every write error seen):
        // into the part file beside the target, renamed onto it by finish_recording (a reader
        // never sees half a recording; one that fails keeps the old file), or into a stream
        // (`/dev/stdout`, a named pipe: its reader waited for, at most files::STREAM_WAIT).
        Sink::Save(path) => {
            let file = open_rrd_file(path)?;
            rrd_file::stream_into(app_id, file).map_err(|e| {
                InspectError::Model(format!("cannot save the recording to {}: {e}", path.display()))
            })?
        }
        Sink::ConnectAndSave(url, path, copy) => {
            let file = open_rrd_file(path)?;
            let (file_sink, handle) = rrd_file::sink_into(file).map_err(|e| {
                InspectError::Model(format!("cannot save the recording to {}: {e}", path.display()))
            })?;
            let rerun::external::re_uri::RedapUri::Proxy(uri) = url.parse().map_err(|e| {
                InspectError::Model(format!(
                    "{url} is not a viewer's URL (rerun+http://HOST:PORT/proxy): {e}"
                ))
            })?
            else {
                return Err(InspectError::Model(format!(
                    "{url} is not a viewer's URL (rerun+http://HOST:PORT/proxy)"
                )));
            };
            copy.0.set(handle).ok();
            let grpc: Box<dyn rerun::sink::LogSink> = Box::new(rerun::sink::GrpcSink::new(uri));
            builder()
                .set_sinks(vec![file_sink, grpc])
                .map_err(|source| InspectError::Open {
                    what: format!("connecting to {url}"),
                    source,
                })?
        }
        Sink::Connect(url) => {
            builder()
                .connect_grpc_opts(url.clone())
                .map_err(|source| InspectError::Open {
                    what: format!("connecting to {url}"),
                    source,
                })?
        }
        // A viewer that cannot start is an error here: the caller chooses a fallback file before
        // its outputs are guarded (the command line resolves `--spawn` with [`spawn_viewer`]).
        Sink::Spawn => builder().spawn().map_err(|source| InspectError::Open {
            what: "spawning a Rerun viewer".into(),
            source,
        })?,
    };
    rec.set_log_time_enabled(false);
    let sent = layout().send(app_id, &rec).map_err(|source| InspectError::Log {
        entity: "the layout (blueprint)".into(),
        source,
    })?;
    Ok((rec, sent))
}

/// Logs a static archetype, mapping the error to one that names the entity.
pub(crate) fn log_static(
    rec: &RecordingStream,
    entity: &str,
    what: &impl rerun::AsComponents,
) -> Result<(), InspectError> {
    rec.log_static(entity, what).map_err(|source| InspectError::Log {
        entity: entity.to_string(),
        source,
    })
}

/// A cross-section point (Y, Z) in m → stored `[Y, −Z]` in mm (see the module doc).
#[inline]
pub fn section_mm(y: f64, z: f64) -> [f32; 2] {
    [(y * 1e3) as f32, (-z * 1e3) as f32]
}

/// A scale bar under a 2D drawing: `length` (in the drawing's units) from the lower left of
/// `points` (stored `[x, −z]`: lower is larger), labelled `label`, at `entity`.
pub(crate) fn log_scale_bar(
    rec: &RecordingStream,
    entity: &str,
    points: &[[f32; 2]],
    length: f32,
    label: &str,
) -> Result<(), InspectError> {
    let (x0, y1) = points
        .iter()
        .fold((f32::INFINITY, f32::NEG_INFINITY), |(x, y), p| {
            (x.min(p[0]), y.max(p[1]))
        });
    if !x0.is_finite() || !y1.is_finite() {
        return Ok(());
    }
    let y = y1 + 0.3 * length;
    log_static(
        rec,
        entity,
        &rerun::LineStrips2D::new([vec![
            [x0, y - 0.15 * length],
            [x0, y],
            [x0 + length, y],
            [x0 + length, y - 0.15 * length],
        ]])
        .with_colors([Color::from_rgb(200, 200, 200)])
        .with_radii([rerun::Radius::new_ui_points(1.0)])
        .with_labels([label]),
    )
}

/// The paper's accuracy bounds of KEC against the tables (Sec. 5, Fig. 18): 1 mm lateral, 0.5 mrad
/// yaw.
pub const PAPER_BOUNDS: [(&str, f64); 2] = [("dy_mm", 1.0), ("dyaw_mrad", 0.5)];

/// A bound drawn in a plot: a grey line at `value` over the first and last entries of
/// `timelines` (each holding those two times), under `entity` (`…/bound`), named `label`.
pub(crate) fn log_bound(
    rec: &RecordingStream,
    timelines: Vec<TimeColumn>,
    entity: &str,
    value: f64,
    label: &str,
) -> Result<(), InspectError> {
    send_scalar_rows(
        rec,
        timelines,
        2,
        entity,
        vec![value, value],
        &[label],
        vec![Color::from_rgb(150, 150, 150)],
    )
}

/// Scalar series against a sequence timeline, sent as columns: `values` holds `names.len()`
/// values per tick (one line each, named and coloured).
pub(crate) fn send_scalar_columns(
    rec: &RecordingStream,
    timeline: &'static str,
    entity: &str,
    ticks: &[i64],
    values: Vec<f64>,
    names: &[&str],
    colors: Vec<Color>,
) -> Result<(), InspectError> {
    send_scalar_rows(
        rec,
        vec![TimeColumn::new_sequence(timeline, ticks.iter().copied())],
        ticks.len(),
        entity,
        values,
        names,
        colors,
    )
}

/// Scalar series on any timelines (each of `rows` entries), sent as columns: `values` holds
/// `names.len()` values per row.
pub(crate) fn send_scalar_rows(
    rec: &RecordingStream,
    timelines: Vec<TimeColumn>,
    rows: usize,
    entity: &str,
    values: Vec<f64>,
    names: &[&str],
    colors: Vec<Color>,
) -> Result<(), InspectError> {
    log_static(
        rec,
        entity,
        &SeriesLines::new()
            .with_names(names.iter().copied())
            .with_colors(colors),
    )?;
    send_scalar_values(rec, timelines, rows, entity, values, names.len())
}

/// The values of scalar series (styled elsewhere) on any timelines (each of `rows` entries), sent
/// as columns: `values` holds `per_row` values per row.
pub(crate) fn send_scalar_values(
    rec: &RecordingStream,
    timelines: Vec<TimeColumn>,
    rows: usize,
    entity: &str,
    values: Vec<f64>,
    per_row: usize,
) -> Result<(), InspectError> {
    let log_err = |source: rerun::RecordingStreamError| InspectError::Log {
        entity: entity.to_string(),
        source,
    };
    let columns = Scalars::new(values)
        .columns(std::iter::repeat_n(per_row, rows))
        .map_err(|e| log_err(e.into()))?;
    rec.send_columns(entity, timelines, columns).map_err(log_err)
}
