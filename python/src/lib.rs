//! `kecsim._kecsim`: the native part of the `kecsim` Python package, a thin layer over the
//! library's facade ([`kecsim::api`]). A run goes on a thread of its own that never holds the
//! GIL; the calling thread waits for it, checks for signals every 50 ms and calls the progress
//! callback itself (the run's thread asks it to and waits for the answer), so that Ctrl-C stops
//! the run at its next step (the run's stop request) and raises `kecsim.Interrupted` carrying what
//! it computed — also while the callback runs, which Python's handler then interrupts. Arrays are
//! handed to numpy without a copy (each column's `Vec<f64>` becomes the array's buffer).
//!
//! Python values become TOML values within the library's bounds on a value set by key (depth,
//! entries, characters: [`kecsim::study::spec::check_value`]), checked as they are converted, so
//! that a list that contains itself or a million entries is refused before it is walked.

use std::sync::mpsc;
use std::time::Duration;

use numpy::PyArray1;
use pyo3::exceptions::{PyKeyboardInterrupt, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};

use kecsim::api::{self, Columns, Progress, ProgressCallback, RunConfig, SceneInput, Value};
use kecsim::dynamics::CancelToken;
use kecsim::study::spec::{
    check_key_path, clipped, MAX_STRING_CHARS, MAX_VALUE_CHARS, MAX_VALUE_DEPTH, MAX_VALUE_ENTRIES,
};

/// How often the waiting thread looks for a signal (Ctrl-C), s.
const SIGNAL_POLL: Duration = Duration::from_millis(50);

/// An instance of the exception class `class` of `kecsim._errors` with `message`.
fn kecsim_error(py: Python<'_>, class: &str, message: String) -> PyErr {
    match py
        .import("kecsim._errors")
        .and_then(|m| m.getattr(class))
        .and_then(|c| c.call1((message,)))
    {
        Ok(instance) => PyErr::from_value(instance),
        Err(import_failed) => import_failed,
    }
}

/// The Python exception for a facade error: `kecsim.ScenarioError` for what the scenario or an
/// override says (file, line, key in the message), `kecsim.BuildError` for what cannot be built
/// from it, `ValueError` for an option.
fn raise(py: Python<'_>, e: api::Error) -> PyErr {
    let class = match &e {
        api::Error::Scenario(_) | api::Error::Source { .. } | api::Error::Override { .. } => "ScenarioError",
        api::Error::Build { .. } | api::Error::Sweep { .. } => "BuildError",
        api::Error::Option(_) => return PyValueError::new_err(e.to_string()),
    };
    kecsim_error(py, class, e.to_string())
}

/// Characters of a key or a value's repr shown in an error (either may be megabytes).
const SHOWN_CHARS: usize = 80;

/// Why an override's Python value has no TOML value: `kind` is the exception class
/// (`ScenarioError`, or `OverrideTypeError` — a ScenarioError and a TypeError — for a type with
/// no TOML form), `problem` what is wrong and the limit.
struct Unconvertible {
    kind: &'static str,
    problem: String,
}

/// How much of the bounds a value being converted has used.
#[derive(Default)]
struct Used {
    entries: usize,
    chars: usize,
}

/// A Python value, shown bounded: a container by its type and length (its repr could be
/// megabytes, or endless), anything else by its repr's beginning.
fn shown(v: &Bound<'_, PyAny>) -> String {
    let kind = v
        .get_type()
        .name()
        .map_or_else(|_| "object".to_string(), |n| n.to_string());
    if v.is_instance_of::<PyList>() || v.is_instance_of::<PyTuple>() || v.is_instance_of::<PyDict>() {
        return format!("a {kind} of {} entries", v.len().unwrap_or(0));
    }
    if let Ok(s) = v.cast::<PyString>() {
        if s.len().unwrap_or(0) > SHOWN_CHARS {
            let text = s.to_cow().map(|t| clipped(&t, SHOWN_CHARS).into_owned());
            return text.unwrap_or_else(|_| format!("a str of {} characters", s.len().unwrap_or(0)));
        }
    }
    if v.is_instance_of::<PyInt>() {
        // (repr of an integer of 1e5 digits raises; its size is what matters.)
        if let Ok(bits) = v.call_method0("bit_length").and_then(|b| b.extract::<u64>()) {
            if bits > 64 {
                return format!("an integer of {bits} bits");
            }
        }
    }
    v.repr().map_or_else(
        |_| format!("a {kind}"),
        |r| clipped(&r.to_string(), SHOWN_CHARS).into_owned(),
    )
}

/// A Python value as a TOML value (for an override): a bool, an int (64-bit), a float, a str, a
/// list or tuple of them, or a number through `float()` (numpy scalars); nested at most
/// [`MAX_VALUE_DEPTH`] levels, [`MAX_VALUE_ENTRIES`] entries in all, each string at most
/// [`MAX_STRING_CHARS`] characters and all at most [`MAX_VALUE_CHARS`] (checked before each
/// level is walked).
fn toml_value(v: &Bound<'_, PyAny>, depth: usize, used: &mut Used) -> Result<Value, Unconvertible> {
    let refused = |problem: String| Unconvertible {
        kind: "ScenarioError",
        problem,
    };
    if depth > MAX_VALUE_DEPTH {
        return Err(refused(format!(
            "a value nested deeper than {MAX_VALUE_DEPTH} levels (lists in lists; a list that contains itself?): at most {MAX_VALUE_DEPTH}"
        )));
    }
    used.entries += 1;
    if v.is_instance_of::<PyBool>() {
        return Ok(Value::Boolean(v.is_truthy().unwrap_or(false)));
    }
    if v.is_instance_of::<PyInt>() {
        return v.extract::<i64>().map(Value::Integer).map_err(|_| {
            refused(
                "an integer outside the 64-bit range of TOML's integers: give a float or an integer within ±9.2e18"
                    .into(),
            )
        });
    }
    if let Ok(f) = v.cast::<PyFloat>() {
        return Ok(Value::Float(f.value()));
    }
    if let Ok(s) = v.cast::<PyString>() {
        let n = s.len().unwrap_or(usize::MAX);
        if n > MAX_STRING_CHARS {
            return Err(refused(format!(
                "a string of {n} characters: at most {MAX_STRING_CHARS}"
            )));
        }
        used.chars += n;
        if used.chars > MAX_VALUE_CHARS {
            return Err(refused(format!(
                "strings of more than {MAX_VALUE_CHARS} characters in all: at most {MAX_VALUE_CHARS}"
            )));
        }
        return s
            .to_cow()
            .map(|t| Value::String(t.into_owned()))
            .map_err(|_| refused("a str that is not valid Unicode (a lone surrogate)".into()));
    }
    let items: Option<Vec<Bound<'_, PyAny>>> = if let Ok(l) = v.cast::<PyList>() {
        // (Counted before the entries are copied out: a list of 1e7 is refused at once.)
        if used.entries + l.len() > MAX_VALUE_ENTRIES {
            None
        } else {
            Some(l.iter().collect())
        }
    } else if let Ok(t) = v.cast::<PyTuple>() {
        if used.entries + t.len() > MAX_VALUE_ENTRIES {
            None
        } else {
            Some(t.iter().collect())
        }
    } else {
        // numpy scalars and other numbers: through float() (not for a dict, bytes or an object).
        if let Ok(f) = v.call_method0("__float__").and_then(|f| f.extract::<f64>()) {
            return Ok(Value::Float(f));
        }
        let kind = v
            .get_type()
            .name()
            .map_or_else(|_| "object".to_string(), |n| n.to_string());
        return Err(Unconvertible {
            kind: "OverrideTypeError",
            problem: format!(
                "a {kind} has no TOML form: expected a number, a string, a bool or a list of them"
            ),
        });
    };
    let Some(items) = items else {
        return Err(refused(format!(
            "a value of more than {MAX_VALUE_ENTRIES} entries in all (lists and their entries): at most {MAX_VALUE_ENTRIES}"
        )));
    };
    let mut out = Vec::with_capacity(items.len());
    for x in &items {
        out.push(toml_value(x, depth + 1, used)?);
    }
    Ok(Value::Array(out))
}

/// The scene: a path (str or os.PathLike) or TOML text, with the overrides applied in order.
fn scene_input(
    py: Python<'_>,
    scene: &Bound<'_, PyAny>,
    overrides: Option<&Bound<'_, PyDict>>,
) -> PyResult<SceneInput> {
    let mut input = if let Ok(text) = scene.extract::<String>() {
        SceneInput::path_or_toml(&text)
    } else if let Ok(path) = scene.call_method0("__fspath__") {
        let path: String = path.extract()?;
        SceneInput::file(path)
    } else {
        return Err(PyTypeError::new_err(
            "scene: expected a path (str or os.PathLike) or TOML text",
        ));
    }
    .map_err(|e| raise(py, e))?;
    if let Some(overrides) = overrides {
        let origin = input.origin().to_string();
        for (k, v) in overrides.iter() {
            let key: String = match k.cast::<PyString>().map(|s| s.to_cow()) {
                Ok(Ok(key)) => key.into_owned(),
                Ok(Err(_)) => {
                    return Err(kecsim_error(
                        py,
                        "ScenarioError",
                        format!(
                            "{origin}: override {}: a key that is not valid Unicode (a lone surrogate)",
                            shown(&k)
                        ),
                    ))
                }
                Err(_) => {
                    return Err(kecsim_error(
                        py,
                        "OverrideTypeError",
                        format!(
                            "{origin}: overrides: a key {} is not a key path (a str, e.g. \"simulation.speed_m_s\")",
                            shown(&k)
                        ),
                    ))
                }
            };
            // The key first, bounded: a key of 50 000 parts named by its beginning.
            check_key_path(&key).map_err(|problem| {
                kecsim_error(
                    py,
                    "ScenarioError",
                    format!("{origin}: override `{}`: {problem}", clipped(&key, SHOWN_CHARS)),
                )
            })?;
            let value = toml_value(&v, 1, &mut Used::default()).map_err(|u| {
                kecsim_error(
                    py,
                    u.kind,
                    format!("{origin}: override `{key}` = {}: {}", shown(&v), u.problem),
                )
            })?;
            input.set(&key, value).map_err(|e| raise(py, e))?;
        }
    }
    Ok(input)
}

/// A dict of column name → numpy array (the columns' buffers handed over, no copy).
fn columns_dict<'py>(py: Python<'py>, columns: Columns) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    for c in columns.columns {
        d.set_item(c.name, PyArray1::from_vec(py, c.values))?;
    }
    Ok(d)
}

/// A JSON value as Python objects (through the json module: the same dict `json.load` gives
/// of the CLI's file).
fn json_to_py<'py>(py: Python<'py>, v: &serde_json::Value) -> PyResult<Bound<'py, PyAny>> {
    let text = serde_json::to_string(v).map_err(|e| PyValueError::new_err(e.to_string()))?;
    py.import("json")?.call_method1("loads", (text,))
}

/// What `kecsim.run` returns.
#[pyclass(module = "kecsim", name = "RunResult", frozen)]
struct PyRunResult {
    /// The wheelset's name → its CSV's column names → numpy arrays (one value per output sample).
    #[pyo3(get)]
    wheelsets: Py<PyDict>,
    /// The summary: the keys of `kecsim run --json`.
    #[pyo3(get)]
    summary: Py<PyAny>,
    /// The run was stopped (Ctrl-C, or a progress callback that returned False).
    #[pyo3(get)]
    interrupted: bool,
    /// Why the run failed (a derailment, the integrator), or None.
    #[pyo3(get)]
    failure: Option<String>,
}

#[pymethods]
impl PyRunResult {
    fn __repr__(&self, py: Python<'_>) -> PyResult<String> {
        let names: Vec<String> = self.wheelsets.bind(py).keys().extract()?;
        let outcome = self
            .summary
            .bind(py)
            .get_item("outcome")
            .and_then(|o| o.extract::<String>())
            .unwrap_or_default();
        Ok(format!(
            "<kecsim.RunResult {outcome}{}: {} wheelsets ({})>",
            if self.interrupted { ", interrupted" } else { "" },
            names.len(),
            names.join(", ")
        ))
    }
}

fn run_result(py: Python<'_>, r: api::RunResult) -> PyResult<PyRunResult> {
    let summary = json_to_py(py, &r.summary_json())?.unbind();
    let wheelsets = PyDict::new(py);
    for w in r.wheelsets {
        wheelsets.set_item(w.name, columns_dict(py, w.series)?)?;
    }
    Ok(PyRunResult {
        wheelsets: wheelsets.unbind(),
        summary,
        interrupted: r.interrupted,
        failure: r.failure,
    })
}

/// What the run's thread sends the waiting thread: a progress report to hand to the callback
/// (answered on the channel that comes with it: go on or stop), or the run's end.
enum Message {
    Progress(Progress, mpsc::SyncSender<bool>),
    Done(Box<Result<api::RunResult, RunFailed>>),
}

/// What stops a run from the waiting thread's side, the first of them kept.
#[derive(Default)]
struct Stops {
    /// A signal's exception (Ctrl-C: KeyboardInterrupt), raised after the run.
    signal: Option<PyErr>,
    /// The progress callback's exception, raised after the run.
    callback_error: Option<PyErr>,
}

impl Stops {
    fn any(&self) -> bool {
        self.signal.is_some() || self.callback_error.is_some()
    }

    /// Runs Python's signal handlers (Ctrl-C raises KeyboardInterrupt there); false once one
    /// asked to stop.
    fn check_signals(&mut self, py: Python<'_>) -> bool {
        if let Err(e) = py.check_signals() {
            self.signal.get_or_insert(e);
        }
        self.signal.is_none()
    }

    /// Hands `p` to the callback, unless a stop was asked or a signal is pending; whether the run
    /// goes on. None or a true answer goes on; any other answer (False, numpy.False_, 0) stops it;
    /// an exception stops it and is kept (a KeyboardInterrupt as the signal: Ctrl-C arrived while
    /// the callback ran).
    fn progress(&mut self, py: Python<'_>, callback: &Py<PyAny>, p: &Progress) -> bool {
        if self.any() || !self.check_signals(py) {
            return false;
        }
        let answer = callback
            .call1(py, (p.t_s, p.duration_s))
            .and_then(|a| match a.is_none(py) {
                true => Ok(true),
                false => a.bind(py).is_truthy(),
            });
        match answer {
            Ok(go) => go,
            Err(e) if e.is_instance_of::<PyKeyboardInterrupt>(py) => {
                self.signal.get_or_insert(e);
                false
            }
            Err(e) => {
                self.callback_error.get_or_insert(e);
                false
            }
        }
    }
}

/// Runs `scene` (see the package's `run`).
#[pyfunction]
#[pyo3(signature = (scene, overrides=None, *, contact=None, threads=None, progress=None, save=None))]
fn run(
    py: Python<'_>,
    scene: &Bound<'_, PyAny>,
    overrides: Option<&Bound<'_, PyDict>>,
    contact: Option<String>,
    threads: Option<usize>,
    progress: Option<Py<PyAny>>,
    save: Option<std::path::PathBuf>,
) -> PyResult<PyRunResult> {
    let input = scene_input(py, scene, overrides)?;
    #[cfg(not(feature = "viewer"))]
    if let Some(path) = &save {
        return Err(PyValueError::new_err(format!(
            "save={}: this kecsim package was built without the viewer (Rerun); build it with `pip install ./python --config-settings=build-args=\"--features viewer\"`",
            path.display()
        )));
    }
    let cancel = CancelToken::new();
    let (tx, rx) = mpsc::channel::<Message>();
    // The callback is called by this thread, not the run's: the run's thread asks for it and
    // waits for the answer, never holding the GIL; once a stop is asked it asks no more.
    let progress_fn: Option<ProgressCallback<'static>> = progress.as_ref().map(|_| {
        let cancel = cancel.clone();
        let tx = tx.clone();
        Box::new(move |p: &Progress| {
            if cancel.requested() {
                return;
            }
            let (answer_tx, answer_rx) = mpsc::sync_channel(1);
            let go = tx.send(Message::Progress(*p, answer_tx)).is_ok() && answer_rx.recv().unwrap_or(false);
            if !go {
                cancel.request();
            }
        }) as ProgressCallback<'static>
    });
    let config = RunConfig {
        contact,
        threads,
        cancel: cancel.clone(),
        progress: progress_fn,
        ..RunConfig::default()
    };
    // The run on a thread of its own, the GIL released; this thread waits for it, looking for
    // signals (Python's handlers run on the main thread only, with the GIL) and calling the
    // progress callback when the run asks.
    let mut stops = Stops::default();
    let (input, save, progress, cancel, stops_here) = (&input, &save, &progress, &cancel, &mut stops);
    // (`move`: the receiver goes to the closure, which may then run on another thread.)
    let outcome = py.detach(move || {
        std::thread::scope(|s| {
            s.spawn(move || {
                let result = input
                    .compile()
                    .map_err(RunFailed::from)
                    .and_then(|scene| run_scene(input, &scene, config, save.as_deref()));
                let _ = tx.send(Message::Done(Box::new(result)));
            });
            loop {
                match rx.recv_timeout(SIGNAL_POLL) {
                    Ok(Message::Done(result)) => break *result,
                    Ok(Message::Progress(p, answer)) => {
                        let go = match &progress {
                            Some(callback) => Python::attach(|py| stops_here.progress(py, callback, &p)),
                            None => true,
                        };
                        if !go {
                            cancel.request();
                        }
                        let _ = answer.send(go);
                    }
                    Err(mpsc::RecvTimeoutError::Timeout) => {
                        if stops_here.signal.is_none() && !Python::attach(|py| stops_here.check_signals(py)) {
                            cancel.request();
                        }
                    }
                    Err(mpsc::RecvTimeoutError::Disconnected) => {
                        break Err(RunFailed::Panicked);
                    }
                }
            }
        })
    });
    let Stops {
        signal,
        callback_error,
    } = stops;
    let result = match outcome {
        Ok(r) => run_result(py, r)?,
        Err(RunFailed::Api(e)) => return Err(signal.unwrap_or_else(|| raise(py, e))),
        Err(RunFailed::Recording(m)) => return Err(signal.unwrap_or_else(|| PyValueError::new_err(m))),
        Err(RunFailed::Output(m)) => return Err(signal.unwrap_or_else(|| kecsim_error(py, "OutputError", m))),
        Err(RunFailed::Panicked) => {
            return Err(pyo3::exceptions::PyRuntimeError::new_err(
                "the run's thread panicked (a kecsim bug: please report it with the scene)",
            ))
        }
    };
    if let Some(e) = callback_error {
        return Err(e);
    }
    if let Some(e) = signal {
        if e.is_instance_of::<PyKeyboardInterrupt>(py) {
            let interrupted = py.import("kecsim._errors")?.getattr("Interrupted")?.call1((
                "interrupted: the run stopped at its next step; what it computed is the exception's .result",
            ))?;
            interrupted.setattr("result", Py::new(py, result)?)?;
            return Err(PyErr::from_value(interrupted));
        }
        return Err(e);
    }
    Ok(result)
}

/// Why a run gave no result.
enum RunFailed {
    Api(api::Error),
    #[cfg_attr(not(feature = "viewer"), allow(dead_code))]
    Recording(String),
    /// `save=` refused by the output guard (an input, read-only, locked).
    #[cfg_attr(not(feature = "viewer"), allow(dead_code))]
    Output(String),
    Panicked,
}

impl From<api::Error> for RunFailed {
    fn from(e: api::Error) -> Self {
        RunFailed::Api(e)
    }
}

#[cfg(not(feature = "viewer"))]
fn run_scene(
    _input: &SceneInput,
    scene: &kecsim::scenario::Scene,
    config: RunConfig<'_>,
    _save: Option<&std::path::Path>,
) -> Result<api::RunResult, RunFailed> {
    Ok(api::run(scene, config)?)
}

/// `save=` through the output guard of `kecsim run --save` ([`kecsim::files::OutputGuard`]):
/// refused where it is a file the scene reads (by any name: a link, another spelling), read-only,
/// or locked by another writer — another process, or another thread of this one (the lock is
/// per open file) — and locked until the recording is written.
#[cfg(feature = "viewer")]
fn guard_save(
    input: &SceneInput,
    scene: &kecsim::scenario::Scene,
    path: &std::path::Path,
) -> Result<kecsim::files::OutputGuard, RunFailed> {
    use kecsim::files::{GuardError, OutputGuard};
    let mut guard = OutputGuard::new();
    guard.inputs(input.files_read(scene));
    guard.output("save=", path).map_err(|e| {
        RunFailed::Output(match e {
            GuardError::Locked { what, path, pid } if pid == std::process::id().to_string() => format!(
                "{what} {path}: another run in this process (pid {pid}: another thread) is writing this file; wait for it to end or choose another path"
            ),
            other => other.to_string(),
        })
    })?;
    Ok(guard)
}

/// With the viewer: `save=` records the run as `kecsim run --save` does, guarded as it is.
#[cfg(feature = "viewer")]
fn run_scene(
    input: &SceneInput,
    scene: &kecsim::scenario::Scene,
    config: RunConfig<'_>,
    save: Option<&std::path::Path>,
) -> Result<api::RunResult, RunFailed> {
    use kecsim::inspect::{run::LiveRecorder, run::RunTab, world3d::World3dSettings, Sink};
    let Some(path) = save else {
        return Ok(api::run(scene, config)?);
    };
    // Held (the lock) until the recording is written.
    let _guard = guard_save(input, scene, path)?;
    let sink = Sink::Save(path.to_path_buf());
    let names = api::wheelset_names(scene)?;
    let world = World3dSettings {
        exaggerate: kecsim::inspect::world3d::DEFAULT_EXAGGERATION,
    };
    let mut recorder = LiveRecorder::open_on(&sink, scene, &names, &world, RunTab::Overview)
        .map_err(|e| RunFailed::Recording(format!("save={}: {e}", path.display())))?;
    let RunConfig {
        contact,
        threads,
        cancel,
        progress,
        ..
    } = config;
    let result = api::run(
        scene,
        RunConfig {
            contact,
            threads,
            cancel,
            progress,
            observers: vec![&mut recorder],
        },
    );
    let delivered = recorder.finish_stream(&sink);
    let result = result?;
    delivered.map_err(|e| RunFailed::Recording(format!("save={}: {e}", path.display())))?;
    Ok(result)
}

/// The contact sweep of `scene`'s wheel–rail pair.
#[pyfunction]
#[pyo3(signature = (scene, overrides=None, *, step_mm=None, y_max_mm=None))]
fn contact_sweep<'py>(
    py: Python<'py>,
    scene: &Bound<'py, PyAny>,
    overrides: Option<&Bound<'py, PyDict>>,
    step_mm: Option<f64>,
    y_max_mm: Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let input = scene_input(py, scene, overrides)?;
    // Checked as `kecsim contact --step --y-max` checks them (the half-range against the
    // pair's flange climb by the sweep itself).
    let settings = api::sweep_settings(step_mm, y_max_mm).map_err(|e| raise(py, e))?;
    let sweep = py
        .detach(|| input.compile().and_then(|s| api::contact_sweep(&s, &settings)))
        .map_err(|e| raise(py, e))?;
    let d = PyDict::new(py);
    d.set_item("table", columns_dict(py, sweep.table)?)?;
    let conicity = PyDict::new(py);
    let amplitude: Vec<f64> = sweep.conicity.iter().map(|c| c.0).collect();
    let annex_b: Vec<f64> = sweep.conicity.iter().map(|c| c.1.unwrap_or(f64::NAN)).collect();
    let regression: Vec<f64> = sweep.conicity.iter().map(|c| c.2.unwrap_or(f64::NAN)).collect();
    conicity.set_item("amplitude_mm", PyArray1::from_vec(py, amplitude))?;
    conicity.set_item("annex_b", PyArray1::from_vec(py, annex_b))?;
    conicity.set_item("regression", PyArray1::from_vec(py, regression))?;
    d.set_item("conicity", conicity)?;
    d.set_item("report", sweep.report)?;
    Ok(d)
}

/// The wheel and rail profiles of `scene`.
#[pyfunction]
#[pyo3(signature = (scene, overrides=None))]
fn profiles<'py>(
    py: Python<'py>,
    scene: &Bound<'py, PyAny>,
    overrides: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyDict>> {
    let input = scene_input(py, scene, overrides)?;
    let scene = py.detach(|| input.compile()).map_err(|e| raise(py, e))?;
    let d = PyDict::new(py);
    for p in api::profiles(&scene) {
        let e = PyDict::new(py);
        e.set_item("name", &p.name)?;
        e.set_item("source", &p.source)?;
        e.set_item("y_mm", PyArray1::from_vec(py, p.y_mm))?;
        e.set_item("z_mm", PyArray1::from_vec(py, p.z_mm))?;
        d.set_item(p.kind, e)?;
    }
    Ok(d)
}

/// The scenario `kecsim run` runs without arguments, as TOML text.
#[pyfunction]
fn default_scene() -> &'static str {
    kecsim::scenario::DEFAULT_SCENARIO
}

/// The columns of a wheelset's time series, in order (the CSV's header).
#[pyfunction]
fn csv_columns() -> Vec<&'static str> {
    kecsim::dynamics::output::CSV_COLUMNS.to_vec()
}

/// Whether this package was built with the viewer (`save=` works).
#[pyfunction]
fn has_viewer() -> bool {
    cfg!(feature = "viewer")
}

#[pymodule]
fn _kecsim(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(run, m)?)?;
    m.add_function(wrap_pyfunction!(contact_sweep, m)?)?;
    m.add_function(wrap_pyfunction!(profiles, m)?)?;
    m.add_function(wrap_pyfunction!(default_scene, m)?)?;
    m.add_function(wrap_pyfunction!(csv_columns, m)?)?;
    m.add_function(wrap_pyfunction!(has_viewer, m)?)?;
    m.add_class::<PyRunResult>()?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
