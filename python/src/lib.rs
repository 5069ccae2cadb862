//! `kecsim._kecsim`: the native part of the `kecsim` Python package, a thin layer over the
//! library's facade ([`kecsim::api`]). A run goes on a thread of its own with the GIL released;
//! the calling thread waits for it and checks for signals every 50 ms, so that Ctrl-C stops the
//! run at its next step (the run's stop request) and raises `kecsim.Interrupted` carrying what it
//! computed. Arrays are handed to numpy without a copy (each column's `Vec<f64>` becomes the
//! array's buffer).

use std::sync::mpsc;
use std::sync::{Arc, Mutex};
use std::time::Duration;

use numpy::PyArray1;
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};

use kecsim::api::{self, Columns, Progress, ProgressCallback, RunConfig, SceneInput, Value};
use kecsim::contact::lookup::TableSettings;
use kecsim::dynamics::CancelToken;

/// How often the waiting thread looks for a signal (Ctrl-C), s.
const SIGNAL_POLL: Duration = Duration::from_millis(50);

/// The Python exception for a facade error: `kecsim.ScenarioError` for what the scenario or an
/// override says (file, line, key in the message), `kecsim.BuildError` for what cannot be built
/// from it, `ValueError` for an option.
fn raise(py: Python<'_>, e: api::Error) -> PyErr {
    let class = match &e {
        api::Error::Scenario(_) | api::Error::Source { .. } | api::Error::Override { .. } => "ScenarioError",
        api::Error::Build { .. } | api::Error::Sweep { .. } => "BuildError",
        api::Error::Option(_) => return PyValueError::new_err(e.to_string()),
    };
    match py
        .import("kecsim._errors")
        .and_then(|m| m.getattr(class))
        .and_then(|c| c.call1((e.to_string(),)))
    {
        Ok(instance) => PyErr::from_value(instance),
        Err(import_failed) => import_failed,
    }
}

/// A Python value as a TOML value (for an override), naming the key where it has no TOML form.
fn toml_value(key: &str, v: &Bound<'_, PyAny>) -> PyResult<Value> {
    if v.is_instance_of::<PyBool>() {
        return Ok(Value::Boolean(v.extract()?));
    }
    if v.is_instance_of::<PyInt>() {
        return Ok(Value::Integer(v.extract()?));
    }
    if v.is_instance_of::<PyFloat>() {
        return Ok(Value::Float(v.extract()?));
    }
    if v.is_instance_of::<PyString>() {
        return Ok(Value::String(v.extract()?));
    }
    if v.is_instance_of::<PyList>() || v.is_instance_of::<PyTuple>() {
        let items: Vec<Bound<'_, PyAny>> = v.try_iter()?.collect::<PyResult<_>>()?;
        return Ok(Value::Array(
            items
                .iter()
                .map(|x| toml_value(key, x))
                .collect::<PyResult<_>>()?,
        ));
    }
    // numpy scalars and other numbers: through float().
    if let Ok(f) = v.call_method0("__float__").and_then(|f| f.extract::<f64>()) {
        return Ok(Value::Float(f));
    }
    Err(PyTypeError::new_err(format!(
        "override `{key}` = {}: expected a number, a string, a bool or a list of them",
        v.repr().map_or_else(|_| "?".to_string(), |r| r.to_string())
    )))
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
        for (k, v) in overrides.iter() {
            let key: String = k.extract().map_err(|_| {
                PyTypeError::new_err("overrides: keys are key paths (str), e.g. \"simulation.speed_m_s\"")
            })?;
            let value = toml_value(&key, &v)?;
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
    let cancel = CancelToken::new();
    // The first error of the progress callback (it stops the run; raised after it).
    let callback_error: Arc<Mutex<Option<PyErr>>> = Arc::new(Mutex::new(None));
    let progress_fn: Option<ProgressCallback<'static>> = progress.map(|callback| {
        let cancel = cancel.clone();
        let error = callback_error.clone();
        Box::new(move |p: &Progress| {
            Python::attach(|py| match callback.call1(py, (p.t_s, p.duration_s)) {
                Ok(answer) => {
                    if answer.bind(py).is(PyBool::new(py, false)) {
                        cancel.request();
                    }
                }
                Err(e) => {
                    error.lock().expect("not poisoned").get_or_insert(e);
                    cancel.request();
                }
            })
        }) as ProgressCallback<'static>
    });
    #[cfg(not(feature = "viewer"))]
    if let Some(path) = &save {
        return Err(PyValueError::new_err(format!(
            "save={}: this kecsim package was built without the viewer (Rerun); build it with `pip install ./python --config-settings=build-args=\"--features viewer\"`",
            path.display()
        )));
    }
    let config = RunConfig {
        contact,
        threads,
        cancel: cancel.clone(),
        progress: progress_fn,
        ..RunConfig::default()
    };
    // The run on a thread of its own, the GIL released; this thread waits for it, looking for
    // signals (Python's handlers run on the main thread only, with the GIL).
    let mut signal: Option<PyErr> = None;
    let outcome = py.detach(|| {
        std::thread::scope(|s| {
            let (tx, rx) = mpsc::channel();
            let input = &input;
            let save = &save;
            s.spawn(move || {
                let result = input
                    .compile()
                    .map_err(RunFailed::from)
                    .and_then(|scene| run_scene(&scene, config, save.as_deref()));
                let _ = tx.send(result);
            });
            loop {
                match rx.recv_timeout(SIGNAL_POLL) {
                    Ok(result) => break result,
                    Err(mpsc::RecvTimeoutError::Timeout) => {
                        if signal.is_none() {
                            if let Err(e) = Python::attach(|py| py.check_signals()) {
                                signal = Some(e);
                                cancel.request();
                            }
                        }
                    }
                    Err(mpsc::RecvTimeoutError::Disconnected) => {
                        break Err(RunFailed::Panicked);
                    }
                }
            }
        })
    });
    let result = match outcome {
        Ok(r) => run_result(py, r)?,
        Err(RunFailed::Api(e)) => return Err(signal.unwrap_or_else(|| raise(py, e))),
        Err(RunFailed::Recording(m)) => return Err(signal.unwrap_or_else(|| PyValueError::new_err(m))),
        Err(RunFailed::Panicked) => {
            return Err(pyo3::exceptions::PyRuntimeError::new_err(
                "the run's thread panicked (a kecsim bug: please report it with the scene)",
            ))
        }
    };
    if let Some(e) = callback_error.lock().expect("not poisoned").take() {
        return Err(e);
    }
    if let Some(e) = signal {
        if e.is_instance_of::<pyo3::exceptions::PyKeyboardInterrupt>(py) {
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
    Panicked,
}

impl From<api::Error> for RunFailed {
    fn from(e: api::Error) -> Self {
        RunFailed::Api(e)
    }
}

#[cfg(not(feature = "viewer"))]
fn run_scene(
    scene: &kecsim::scenario::Scene,
    config: RunConfig<'_>,
    _save: Option<&std::path::Path>,
) -> Result<api::RunResult, RunFailed> {
    Ok(api::run(scene, config)?)
}

/// With the viewer: `save=` records the run as `kecsim run --save` does.
#[cfg(feature = "viewer")]
fn run_scene(
    scene: &kecsim::scenario::Scene,
    config: RunConfig<'_>,
    save: Option<&std::path::Path>,
) -> Result<api::RunResult, RunFailed> {
    use kecsim::inspect::{run::LiveRecorder, run::RunTab, world3d::World3dSettings, Sink};
    let Some(path) = save else {
        return Ok(api::run(scene, config)?);
    };
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
    let mut settings = TableSettings::default();
    if let Some(step) = step_mm {
        if !(step.is_finite() && step > 0.0 && step <= 5.0) {
            return Err(PyValueError::new_err(format!(
                "step_mm = {step}: expected a step in (0, 5] mm"
            )));
        }
        settings.step_m = step * 1e-3;
    }
    if let Some(m) = y_max_mm {
        if !(m.is_finite() && m > 0.0) {
            return Err(PyValueError::new_err(format!(
                "y_max_mm = {m}: expected a positive half-range, mm"
            )));
        }
        settings.y_max_m = Some(m * 1e-3);
    }
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
