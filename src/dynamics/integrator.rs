//! Time integrators for x' = f(t, x) with error control, fixed-rate output and diagnosis.
//!
//! - [`Method::Dopri5`]: Dormand–Prince 5(4), explicit, FSAL, PI step-size control and the
//!   4th-order continuous extension of Hairer's DOPRI5 for output between steps. Efficient while
//!   the step is limited by accuracy.
//! - [`Method::Ros3`]: the L-stable 3-stage Rosenbrock method of order 3 with an embedded order-2
//!   estimate (Sandu et al. 1997, *Benchmarking stiff ODE solvers for atmospheric chemistry
//!   problems II: Rosenbrock solvers*, Atmos. Env. 31; Hairer–Wanner form below), two function
//!   evaluations and one LU decomposition of (1/(hγ) I − J) per step, J by finite differences
//!   unless the system provides it. Stays efficient when creep forces make the wheelset modes stiff
//!   (time constants of milliseconds, DYNAMICS.md §4), where an explicit method is limited by
//!   stability. Output between steps: cubic Hermite with the derivatives at both ends (3rd order,
//!   matching the method).
//!
//! - [`Method::Ros34pw2`]: the Rosenbrock **W-method** ROS34PW2 of Rang & Angermann (2005): 4
//!   stages, order 3 with an embedded order-2 estimate, L-stable and stiffly accurate. A W-method
//!   keeps its order with *any* matrix W in place of ∂f/∂x, so one finite-difference Jacobian (and
//!   f_t) serves up to [`Settings::jacobian_max_age`] accepted steps: 4 right-hand sides per step
//!   plus n + 1 per Jacobian, against 6 for DOPRI5 held at its stability limit by the creep forces.
//!   The Jacobian is renewed after a rejection by a wide margin (err > 10) or a second rejection in
//!   a row; a mild rejection is the step size's fault. Output: cubic Hermite.
//!
//! - [`Method::Bdf`]: variable-step, variable-order BDF (orders 1–5, [`bdf`]) — the family of the
//!   paper's integrator (Matlab's `ode15s`, §8.4). One implicit equation per step, solved by
//!   Newton's method with a matrix that is kept for many steps: the Jacobian's diagonal blocks
//!   (each wheelset, by finite differences; with [`OdeSystem::newton_groups`] also the bogie
//!   frames, in passes of their own) and the exact q̇ = v coupling of the other bodies
//!   ([`OdeSystem::kinematic_blocks`]). About 3–4 right-hand sides per step, steps set by
//!   accuracy, not by the creep forces' stiffness. The matrix is renewed where the Newton
//!   iteration stops converging with it (or after [`Settings::jacobian_max_age`] steps), never for
//!   a step the error test rejects: the BDF solution does not depend on it. Output: cubic Hermite.
//!
//! After a rejected step the next accepted one does not grow the step (Hairer–Wanner I, §II.4).
//!
//! Files: this one holds the system's interface, the settings, the statistics and the one
//! integration loop (step control, events, output); each method's step is in a file of its own —
//! `dopri5`, `rosenbrock` (ROS3, ROS34PW2 and their tableaux),
//! `bdf_step` (with the BDF's formulas in [`bdf`]) —, the finite-difference Jacobian in
//! `jacobian`, the factored Newton matrix in `newton`.
//!
//! Rosenbrock step, both methods by one code path from their tableaux in the standard form
//! (Hairer–Wanner II, §IV.7, (7.4) with W for ∂f/∂x; ROS3 converted from its published
//! transformed coefficients; f_t by a forward difference):
//!
//! ```text
//! (I − γ h W) k_i = h f(t + α_i h, x + Σ_j a_ij k_j) + h W Σ_j γ_ij k_j + γ_i h² f_t
//! x₁ = x + Σ b_i k_i,   err = Σ (b_i − b̂_i) k_i
//! ```
//!
//! Error norm (both methods): RMS over the components of err_i / (atol + rtol max(|x₀ᵢ|, |x₁ᵢ|)),
//! idle components (exactly 0 at both ends, no error) left out.
//! A step is accepted when the norm ≤ 1. Failures are reported, never hidden: the step size
//! collapsing below `h_min` (with the time and the last error norm), too many steps, and a
//! right-hand side that fails or returns non-finite values at every step size tried.

use nalgebra::DMatrix;
use thiserror::Error;

use super::cancel::CancelToken;

/// A first-order system x' = f(t, x).
pub trait OdeSystem {
    /// What a failing evaluation reports (e.g. a wheel that lifts, a contact Newton that fails).
    type Error: std::fmt::Display + std::fmt::Debug;
    /// Number of states.
    fn dim(&self) -> usize;
    /// f(t, x) into `dxdt`. An `Err` at a trial stage rejects the step; if the step size collapses
    /// on it, the integration stops with that diagnosis.
    fn rhs(&mut self, t: f64, x: &[f64], dxdt: &mut [f64]) -> Result<(), Self::Error>;
    /// f(t, x) on at least the rows of `rows` (blocks (offset, size)): the finite-difference
    /// passes over blocks read only those rows, so a system may skip the work the other rows
    /// need. Rows outside `rows` are unspecified. Default: the whole [`Self::rhs`].
    fn rhs_rows(
        &mut self,
        t: f64,
        x: &[f64],
        dxdt: &mut [f64],
        rows: &[(usize, usize)],
    ) -> Result<(), Self::Error> {
        let _ = rows;
        self.rhs(t, x, dxdt)
    }
    /// f(t, x) on every row but those of the blocks of [`Self::reusable_blocks`] marked in
    /// `quiet` (one flag per block), which are unspecified: the BDF's Newton iteration fills them
    /// itself ([`Settings::newton_reuse`]), so a system may skip the work only they need.
    /// Default: the whole [`Self::rhs`].
    fn rhs_reusing(
        &mut self,
        t: f64,
        x: &[f64],
        dxdt: &mut [f64],
        quiet: &[bool],
    ) -> Result<(), Self::Error> {
        let _ = quiet;
        self.rhs(t, x, dxdt)
    }
    /// Blocks (offset, size) whose rows [`Self::rhs_reusing`] can skip, each one of the
    /// [`Self::newton_groups`]' blocks (its rows depend on its own states and on states outside
    /// every block, never on another block's). Default: none.
    fn reusable_blocks(&self) -> Vec<(usize, usize)> {
        Vec::new()
    }
    /// The Jacobian ∂f/∂x, if the system can supply it (else finite differences are used).
    fn jacobian(&mut self, _t: f64, _x: &[f64], _jac: &mut DMatrix<f64>) -> Option<Result<(), Self::Error>> {
        None
    }
    /// Number of event functions (discontinuities such as impacts; default none).
    fn event_count(&self) -> usize {
        0
    }
    /// The event functions g_k(x). Event k happens where g_k passes from > 0 to ≤ 0 within an
    /// accepted step (located on the continuous extension), or is < 0 at its end: the step is
    /// cut there and [`Self::jump`] called.
    fn events(&self, _x: &[f64], _g: &mut [f64]) {}
    /// Applies event `event` at (t, x), changing the state (an impact). The integration goes on
    /// from the changed state with a fresh f(t, x).
    fn jump(&mut self, _t: f64, _event: usize, _x: &mut [f64]) -> Result<(), Self::Error> {
        Ok(())
    }
    /// For W-methods ([`Method::Ros34pw2`]): diagonal blocks (offset, size) that hold the stiff
    /// couplings. W is then the Jacobian restricted to them (every other entry taken as zero),
    /// factored block by block. Contract: a block's rows of f depend on no other block's states
    /// (they may depend on states outside every block), so that one finite-difference evaluation
    /// perturbs the same local column of every block at once — the Jacobian costs as many
    /// evaluations as the largest block has columns. `None`: the full Jacobian.
    fn jacobian_blocks(&self) -> Option<Vec<(usize, usize)>> {
        None
    }
    /// For the BDF's Newton matrix: groups of diagonal blocks, each group with the contract of
    /// [`Self::jacobian_blocks`] (one finite-difference pass per group). `None`: the
    /// [`Self::jacobian_blocks`] as one group.
    fn newton_groups(&self) -> Option<Vec<Vec<(usize, usize)>>> {
        None
    }
    /// For the BDF's Newton matrix: blocks (offset, 2m) of states whose first m derivatives are
    /// exactly their last m states (positions and velocities: x'_{o+i} = x_{o+m+i}). Outside the
    /// [`Self::jacobian_blocks`] the iteration matrix keeps this exact part of the Jacobian
    /// (free), so that the Newton iteration on slow second-order states contracts as (ωh)²
    /// instead of ωh. Default: none.
    fn kinematic_blocks(&self) -> Vec<(usize, usize)> {
        Vec::new()
    }
    /// Whether state j is left out of finite-difference Jacobians at x (its column zero): for
    /// states where a perturbation switches the model rather than moves it.
    fn inactive(&self, _x: &[f64], _j: usize) -> bool {
        false
    }
}

/// What the output observer tells the integrator: go on, or stop here (a stop condition met; the
/// integration then ends normally with [`Completion::Stopped`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Flow {
    Continue,
    Stop,
}

/// How an integration that did not fail ended.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Completion {
    /// It reached t_end.
    Finished,
    /// The observer stopped it at the output time `t`.
    Stopped { t: f64 },
}

/// The integration method.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Method {
    Dopri5,
    Ros3,
    Ros34pw2,
    Bdf,
    Radau5,
}

impl Method {
    /// Every method, in the order of [`Method::NAMES`].
    pub const ALL: [Method; 5] = [
        Method::Dopri5,
        Method::Ros3,
        Method::Ros34pw2,
        Method::Bdf,
        Method::Radau5,
    ];
    /// The one list of method names: the scenario's `[simulation.integrator] method`, the CLI's
    /// `--method` values and the printed name are all these.
    pub const NAMES: [&'static str; 5] = ["dopri5", "ros3", "ros34pw2", "bdf", "radau5"];

    /// The method's name in scenario files and on the command line.
    pub fn name(self) -> &'static str {
        let i = Method::ALL.iter().position(|&m| m == self).unwrap_or_default();
        Method::NAMES[i]
    }
}

impl std::str::FromStr for Method {
    type Err = String;
    /// A method by its name; an unknown name is an error listing the known ones (never a silent
    /// default).
    fn from_str(name: &str) -> Result<Method, String> {
        Method::NAMES
            .iter()
            .position(|&n| n == name)
            .map(|i| Method::ALL[i])
            .ok_or_else(|| {
                format!(
                    "unknown integration method '{name}' (expected one of: {})",
                    Method::NAMES.join(", ")
                )
            })
    }
}

/// BDF: Newton iterations per step before the Jacobian is renewed or the step fails.
const NEWTON_MAX: usize = 4;
/// BDF: the Newton iteration's remaining error, in the error norm (1 = the tolerance), where the
/// settings do not say otherwise ([`Settings::newton_tolerance`]).
pub const NEWTON_TOLERANCE: f64 = 0.1;

/// Tolerances and limits, and the request that stops the integration early.
#[derive(Debug, Clone, PartialEq)]
pub struct Settings {
    pub method: Method,
    pub rtol: f64,
    pub atol: f64,
    /// First step (None: chosen from the tolerances and f(t₀, x₀)).
    pub h_init: Option<f64>,
    pub h_min: f64,
    pub h_max: f64,
    pub max_steps: usize,
    /// Take fixed steps of this size without error control (convergence studies only).
    pub fixed_step: Option<f64>,
    /// ROS34PW2 only: accepted steps a Jacobian is kept for before it is evaluated again
    /// (1 = every step; earlier after a rejection by a wide margin or two rejections in a row).
    pub jacobian_max_age: usize,
    /// BDF only: the highest order used (1–5; BDF-1, BDF-2 are A-stable, BDF-3…5 stable in
    /// narrowing sectors around the negative real axis).
    pub bdf_max_order: usize,
    /// BDF only: the Newton iteration stops when its estimated remaining error is below this
    /// fraction of the local error tolerance (the error norm's 1); CVODE's default is 0.1
    /// ([`NEWTON_TOLERANCE`]). Larger: fewer iterations, the iteration error a larger share of the
    /// step's error (issue 52 measures it on the precision protocol).
    pub newton_tolerance: f64,
    /// BDF only: Newton iterations after the first re-evaluate only the
    /// [`OdeSystem::reusable_blocks`] whose last correction is larger than this fraction of the
    /// Newton tolerance (every term |δᵢ| / (atol + rtol |xᵢ|) of the block); a quieter block's rows
    /// are carried forward to first order with its block of the Jacobian, f ← f + J_bb δ_b.
    /// The iteration then converges to within that first-order error of the full one. 0 (the
    /// default): every iteration evaluates the whole right-hand side.
    pub newton_reuse: f64,
    /// A stop asked for from outside (the binary's Ctrl-C): checked after every step, the
    /// integration then ends there ([`Completion::Stopped`]). Default: a fresh token, never asked.
    pub cancel: CancelToken,
    /// Ends an integration whose step stays collapsed ([`IntegrationError::Stalled`]); None: never.
    pub stall: Option<StallLimit>,
}

/// A collapsed step size: `steps` accepted steps in a row, each shorter than `h_below`. A motion
/// far faster than the model's (a unit mistake: a mass in g, a position in mm, a stiffness in
/// N/mm typed as N/m) grinds on at such steps for hours; a flange impact or a landing takes a
/// few hundred short steps and recovers.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StallLimit {
    pub h_below: f64,
    pub steps: usize,
}

impl Settings {
    pub fn new(method: Method, rtol: f64, atol: f64) -> Settings {
        Settings {
            method,
            rtol,
            atol,
            h_init: None,
            h_min: 1e-12,
            h_max: f64::INFINITY,
            max_steps: 10_000_000,
            fixed_step: None,
            jacobian_max_age: 25,
            bdf_max_order: 5,
            newton_tolerance: NEWTON_TOLERANCE,
            newton_reuse: 0.0,
            cancel: CancelToken::default(),
            stall: None,
        }
    }
}

/// The current run of collapsed steps ([`StallLimit`]): how many, from when, and how often each
/// state's error held them.
struct StallRun {
    steps: usize,
    from: f64,
    limiting: Vec<usize>,
}

/// Why an integration failed; `E` is the system's error.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum IntegrationError<E> {
    #[error("step size collapse at t = {t:.6} s: h = {h:.3e} s < h_min (last error norm {err:.3e})")]
    StepCollapse { t: f64, h: f64, err: f64 },
    /// The right-hand side failed at every step size down to h_min (or at the start).
    #[error("the model failed at t = {t:.6} s: {error}")]
    Model { t: f64, error: E },
    /// The output observer failed.
    #[error("output at t = {t:.6} s: {error}")]
    Output { t: f64, error: E },
    #[error("non-finite state or derivative at t = {t:.6} s (every step size down to h_min tried)")]
    NonFinite { t: f64 },
    #[error("more than {0} steps")]
    MaxSteps(usize),
    /// [`StallLimit`]: the step stayed below `h_below` for `steps` accepted steps in a row, which
    /// advanced the time by `span_s`; `limiting`: the state whose error held most of them.
    #[error("step size collapsed at t = {t:.6} s: {steps} steps in a row shorter than {h_below:.1e} s ({span_s:.2e} s simulated by them)")]
    Stalled {
        t: f64,
        h_below: f64,
        steps: usize,
        span_s: f64,
        limiting: Option<usize>,
    },
    #[error("singular iteration matrix (1/(hγ) I − J) at t = {t:.6} s")]
    Singular { t: f64 },
    #[error("invalid integrator settings: {0}")]
    Settings(SettingsError),
}

/// What is wrong with an integration's settings, or with the layout its system declares.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum SettingsError {
    /// The initial state's length is not the system's number of states.
    #[error("x0 has {given} states, the system {states}")]
    StateCount { given: usize, states: usize },
    /// A tolerance, the output interval or the time span is not positive.
    #[error("need rtol > 0, atol > 0, dt_out > 0, t_end ≥ t0 (rtol {rtol}, atol {atol}, dt_out {dt_out}, t0 {t0}, t_end {t_end})")]
    Tolerances {
        rtol: f64,
        atol: f64,
        dt_out: f64,
        t0: f64,
        t_end: f64,
    },
    /// A Jacobian block ([`OdeSystem::jacobian_blocks`], [`OdeSystem::newton_groups`]) overlaps
    /// another or reaches beyond the states.
    #[error("Jacobian block ({offset}, {size}) overlaps another or reaches beyond the {states} states")]
    JacobianBlock {
        offset: usize,
        size: usize,
        states: usize,
    },
    /// A kinematic block ([`OdeSystem::kinematic_blocks`]) has an odd size or reaches beyond the
    /// states.
    #[error("kinematic block ({offset}, {size}) is odd or reaches beyond the {states} states")]
    KinematicBlock {
        offset: usize,
        size: usize,
        states: usize,
    },
    /// A reusable block ([`OdeSystem::reusable_blocks`]) is not one of the Newton matrix's
    /// blocks, whose Jacobian would carry it forward.
    #[error("reusable block ({offset}, {size}) is not one of the Newton matrix's Jacobian blocks ({states} states)")]
    ReusableBlock {
        offset: usize,
        size: usize,
        states: usize,
    },
}

/// Work done.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Stats {
    pub accepted: usize,
    pub rejected: usize,
    pub rhs_evaluations: usize,
    /// BDF with [`Settings::newton_reuse`]: blocks carried forward by their Jacobian instead of
    /// evaluated, summed over the Newton iterations (each such iteration is still counted in
    /// `rhs_evaluations`).
    pub reused_blocks: usize,
    pub jacobians: usize,
    /// The smallest accepted step but for the last one (cut to land on the end).
    pub smallest_step: f64,
    pub largest_step: f64,
    /// Events located and applied ([`OdeSystem::jump`]).
    pub events: usize,
    /// What limits the step: per state, the accepted and the rejected steps in which it had the
    /// largest term of the error norm (err_i / (atol + rtol max(|x₀ᵢ|, |x₁ᵢ|)) of largest
    /// magnitude). The step size follows the error norm, so the states counted most are the
    /// ones whose motion sets the step (e.g. a flanging wheelset's lateral velocity).
    pub limiting: Vec<[usize; 2]>,
}

/// One state's share in what limited the steps ([`Stats::limiting`]).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct StepLimit {
    /// The state's name (as the caller of [`Stats::limiting_states`] names it; the vehicles':
    /// [`crate::dynamics::VehicleModel::state_names`]).
    pub state: String,
    /// Accepted steps in which it had the largest error term.
    pub accepted_steps: usize,
    /// Rejected steps in which it had the largest error term.
    pub rejected_steps: usize,
    /// Its share of all steps tried (accepted and rejected), 0–1.
    pub share: f64,
}

impl Stats {
    /// The `top` states that limited most steps (accepted and rejected together), most first,
    /// named by `name`.
    pub fn limiting_states(&self, top: usize, name: impl Fn(usize) -> String) -> Vec<StepLimit> {
        let total: usize = self.limiting.iter().map(|c| c[0] + c[1]).sum();
        let mut idx: Vec<usize> = (0..self.limiting.len())
            .filter(|&i| self.limiting[i][0] + self.limiting[i][1] > 0)
            .collect();
        idx.sort_by_key(|&i| (std::cmp::Reverse(self.limiting[i][0] + self.limiting[i][1]), i));
        idx.into_iter()
            .take(top)
            .map(|i| StepLimit {
                state: name(i),
                accepted_steps: self.limiting[i][0],
                rejected_steps: self.limiting[i][1],
                share: (self.limiting[i][0] + self.limiting[i][1]) as f64 / total.max(1) as f64,
            })
            .collect()
    }
}

/// Receives the state at each output time; [`Flow::Stop`] ends the integration normally, an `Err`
/// ends it with [`IntegrationError::Output`].
pub type Observer<'a, E> = dyn FnMut(f64, &[f64]) -> Result<Flow, E> + 'a;

/// Integrates from (t0, x0) to t_end, calling `output(t, x)` at t0 and every `dt_out` after it
/// (and at t_end), whatever the step size. Returns the work done.
pub fn integrate<S: OdeSystem + ?Sized>(
    sys: &mut S,
    t0: f64,
    x0: &[f64],
    t_end: f64,
    dt_out: f64,
    settings: &Settings,
    output: &mut Observer<'_, S::Error>,
) -> Result<Stats, IntegrationError<S::Error>> {
    let mut stats = Stats::default();
    integrate_into(sys, t0, x0, t_end, dt_out, settings, output, &mut stats)?;
    Ok(stats)
}

/// [`integrate`], keeping the work done in `stats` also when it fails or is stopped.
#[allow(clippy::too_many_arguments)]
pub fn integrate_into<S: OdeSystem + ?Sized>(
    sys: &mut S,
    t0: f64,
    x0: &[f64],
    t_end: f64,
    dt_out: f64,
    settings: &Settings,
    output: &mut Observer<'_, S::Error>,
    stats: &mut Stats,
) -> Result<Completion, IntegrationError<S::Error>> {
    let n = sys.dim();
    if x0.len() != n {
        return Err(IntegrationError::Settings(SettingsError::StateCount {
            given: x0.len(),
            states: n,
        }));
    }
    if !(settings.rtol > 0.0 && settings.atol > 0.0 && dt_out > 0.0 && t_end >= t0) {
        return Err(IntegrationError::Settings(SettingsError::Tolerances {
            rtol: settings.rtol,
            atol: settings.atol,
            dt_out,
            t0,
            t_end,
        }));
    }
    *stats = Stats {
        smallest_step: f64::INFINITY,
        limiting: vec![[0, 0]; n],
        ..Stats::default()
    };
    let mut stall = StallRun {
        steps: 0,
        from: t0,
        limiting: vec![0; if settings.stall.is_some() { n } else { 0 }],
    };
    let model = |t: f64| move |error: S::Error| IntegrationError::Model { t, error };
    let out_err = |t: f64| move |error: S::Error| IntegrationError::Output { t, error };
    let mut x = x0.to_vec();
    let mut t = t0;
    let mut f0 = vec![0.0; n];
    sys.rhs(t, &x, &mut f0).map_err(model(t))?;
    stats.rhs_evaluations += 1;
    if !all_finite(&x) || !all_finite(&f0) {
        return Err(IntegrationError::NonFinite { t });
    }
    if output(t, &x).map_err(out_err(t))? == Flow::Stop {
        return Ok(Completion::Stopped { t });
    }
    let mut next_out = t0 + dt_out;
    let mut out_index = 1u64;

    let mut h = match (settings.fixed_step, settings.h_init) {
        (Some(h), _) | (None, Some(h)) => h,
        (None, None) => initial_step(&x, &f0, settings),
    }
    .min(settings.h_max)
    .min((t_end - t0).max(f64::MIN_POSITIVE));
    let mut stepper = Stepper::new(n, settings.method);
    if matches!(settings.method, Method::Bdf | Method::Radau5) {
        let groups = sys
            .newton_groups()
            .or_else(|| sys.jacobian_blocks().map(|b| vec![b]));
        stepper
            .set_blocks(groups, sys.kinematic_blocks(), n)
            .map_err(IntegrationError::Settings)?;
    }
    if settings.method == Method::Bdf && settings.newton_reuse > 0.0 {
        stepper
            .set_reusable(sys.reusable_blocks(), n)
            .map_err(IntegrationError::Settings)?;
    }
    if settings.method == Method::Ros34pw2 {
        stepper
            .set_blocks(sys.jacobian_blocks().map(|b| vec![b]), Vec::new(), n)
            .map_err(IntegrationError::Settings)?;
    }
    let mut x1 = vec![0.0; n];
    let mut f1 = vec![0.0; n];
    let mut err_prev: f64 = 1e-4;
    // Rejections in a row at the current point.
    let mut rejections = 0usize;
    let n_events = sys.event_count();
    let mut g0 = vec![0.0; n_events];
    let mut g1 = vec![0.0; n_events];
    sys.events(&x, &mut g0);
    while t < t_end {
        if stats.accepted + stats.rejected >= settings.max_steps {
            return Err(IntegrationError::MaxSteps(settings.max_steps));
        }
        let last = t + h >= t_end - 1e-14 * t_end.abs().max(1.0);
        if last {
            h = t_end - t;
        }
        stepper.limiting = None;
        let attempt = stepper.step(sys, t, &x, &f0, h, settings, &mut x1, &mut f1, stats);
        let err = match &attempt {
            Ok(e) if e.is_finite() && all_finite(&x1) && all_finite(&f1) => *e,
            Ok(_) => f64::INFINITY,
            // A model failure at a trial stage (a wheel lifting, the contact model off its table)
            // may be the step's fault, not the motion's: reject and retry shorter; if the step
            // collapses on it, it is the motion's, and the model's diagnosis is reported.
            Err(StepFailure::Model(_)) => {
                if h * 0.25 < settings.h_min.max(1e-12 * t.abs().max(1.0)) {
                    let Err(StepFailure::Model(error)) = attempt else {
                        unreachable!("matched above")
                    };
                    return Err(IntegrationError::Model { t, error });
                }
                f64::INFINITY
            }
            Err(StepFailure::Singular) => f64::INFINITY,
        };
        if settings.fixed_step.is_some() && err.is_finite() {
            // No control: accept.
        } else if err > 1.0 {
            stats.rejected += 1;
            if let (Some(i), true) = (stepper.limiting.take(), err.is_finite()) {
                stats.limiting[i][1] += 1;
            }
            rejections += 1;
            let q = stepper.error_order();
            stepper.rejected(err, rejections);
            let fac = stepper.rejection_factor(err, q);
            h *= fac;
            if h < settings.h_min {
                if !err.is_finite() {
                    if matches!(attempt, Err(StepFailure::Singular)) {
                        return Err(IntegrationError::Singular { t });
                    }
                    return Err(IntegrationError::NonFinite { t });
                }
                return Err(IntegrationError::StepCollapse { t, h, err });
            }
            continue;
        }
        if !err.is_finite() {
            return Err(IntegrationError::NonFinite { t });
        }
        // Accepted. An event inside the step cuts it at the event (s_event < 1).
        let event = if n_events > 0 {
            sys.events(&x1, &mut g1);
            first_event(&g0, &g1, |s| {
                let xs = stepper.dense(&x, &x1, &f0, &f1, h, s);
                let mut g = vec![0.0; n_events];
                sys.events(&xs, &mut g);
                g
            })
        } else {
            None
        };
        let t1 = match event {
            Some((_, s)) => t + s * h,
            None => t + h,
        };
        // Output every multiple of dt_out inside (t, t1].
        while next_out <= t1 + 1e-12 * t1.abs().max(1.0) && next_out <= t_end + 1e-12 * t_end.abs().max(1.0) {
            let s = ((next_out - t) / h).clamp(0.0, 1.0);
            let xo = stepper.dense(&x, &x1, &f0, &f1, h, s);
            if output(next_out, &xo).map_err(out_err(next_out))? == Flow::Stop {
                return Ok(Completion::Stopped { t: next_out });
            }
            out_index += 1;
            next_out = t0 + out_index as f64 * dt_out;
        }
        stats.accepted += 1;
        let limiting = stepper.limiting.take();
        if let Some(i) = limiting {
            stats.limiting[i][0] += 1;
        }
        if let Some(limit) = settings.stall {
            if h < limit.h_below && !last {
                if stall.steps == 0 {
                    stall.from = t;
                    stall.limiting.iter_mut().for_each(|c| *c = 0);
                }
                stall.steps += 1;
                if let Some(i) = limiting {
                    stall.limiting[i] += 1;
                }
                if stall.steps >= limit.steps {
                    let most = (0..n).max_by_key(|&i| (stall.limiting[i], std::cmp::Reverse(i)));
                    return Err(IntegrationError::Stalled {
                        t: t1,
                        h_below: limit.h_below,
                        steps: stall.steps,
                        span_s: t1 - stall.from,
                        limiting: most.filter(|&i| stall.limiting[i] > 0),
                    });
                }
            } else {
                stall.steps = 0;
            }
        }
        let q = stepper.error_order();
        stepper.accepted(settings.jacobian_max_age);
        if settings.method == Method::Bdf {
            stepper.bdf_accepted(t + h, &x1, err, h, settings);
        }
        if !last || stats.accepted == 1 {
            // The last step, cut to land on the end, says nothing of the step control.
            stats.smallest_step = stats.smallest_step.min(h);
        }
        stats.largest_step = stats.largest_step.max(h);
        if let Some((k, s)) = event {
            // The state at the event, changed by the jump; f there afresh (no FSAL across it).
            let mut xe = if s < 1.0 {
                stepper.dense(&x, &x1, &f0, &f1, h, s)
            } else {
                x1.clone()
            };
            sys.jump(t1, k, &mut xe).map_err(model(t1))?;
            sys.rhs(t1, &xe, &mut f1).map_err(model(t1))?;
            stats.rhs_evaluations += 1;
            stats.events += 1;
            if !all_finite(&xe) || !all_finite(&f1) {
                return Err(IntegrationError::NonFinite { t: t1 });
            }
            x1.copy_from_slice(&xe);
            stepper.jac_age = None;
            stepper.bdf.restart();
            stepper.radau.restart();
        }
        t = if last && event.is_none() { t_end } else { t1 };
        std::mem::swap(&mut x, &mut x1);
        std::mem::swap(&mut f0, &mut f1);
        if n_events > 0 {
            sys.events(&x, &mut g0);
        }
        if settings.fixed_step.is_none() {
            // PI controller (Gustafsson; Hairer's DOPRI5 uses β = 0.04).
            let beta = 0.04;
            let e = err.max(1e-10);
            let mut fac = if settings.method == Method::Bdf {
                stepper.bdf.factor
            } else if settings.method == Method::Radau5 {
                stepper.radau.factor
            } else {
                (0.9 * e.powf(-1.0 / q + 0.75 * beta) * err_prev.powf(beta)).clamp(0.2, 10.0)
            };
            if rejections > 0 {
                // Right after a rejection, do not grow the step (Hairer–Wanner I, §II.4).
                fac = fac.min(1.0);
            }
            err_prev = e;
            h = (h * fac).min(settings.h_max);
        }
        rejections = 0;
        // A stop asked for from outside (Ctrl-C, SIGTERM: `settings.cancel`): end at this step,
        // with an output here unless the grid just gave one.
        if settings.cancel.requested() && t < t_end {
            let last_out = t0 + (out_index - 1) as f64 * dt_out;
            if (t - last_out).abs() > 1e-12 * t.abs().max(1.0) {
                output(t, &x).map_err(out_err(t))?;
            }
            return Ok(Completion::Stopped { t });
        }
    }
    // The end point, if the output grid did not land on it.
    if (next_out - dt_out - t_end).abs() > 1e-9 * dt_out
        && output(t_end, &x).map_err(out_err(t_end))? == Flow::Stop
    {
        return Ok(Completion::Stopped { t: t_end });
    }
    if stats.accepted == 0 {
        stats.smallest_step = 0.0;
    }
    Ok(Completion::Finished)
}

/// The first event in a step from g0 (at its start) to g1 (at its end): the index and the step
/// fraction s ∈ (0, 1] where it happens. Event k happens where g_k passes from > 0 to ≤ 0: if it
/// is ≤ 0 at the end, the bracket is [0, 1] when it was > 0 at the start, else (it started at 0,
/// e.g. right after its own jump) from the first of 16 samples of the step where it is > 0; the
/// root is located by the Illinois method on `g_at(s)` (the events on the continuous extension)
/// to 1e-10 of the step. No sample > 0 and < 0 at the end: s = 1; < 0 already at the start: s = 0.
fn first_event(g0: &[f64], g1: &[f64], mut g_at: impl FnMut(f64) -> Vec<f64>) -> Option<(usize, f64)> {
    let mut best: Option<(usize, f64)> = None;
    for k in 0..g0.len() {
        if g1[k] > 0.0 || (g1[k] == 0.0 && g0[k] <= 0.0) {
            continue;
        }
        // Already below zero at the step's start (left there by another event's jump at the same
        // instant, e.g. a wheelset's second wheel landing together with the first): at once.
        let s = if g0[k] < 0.0 {
            0.0
        } else {
            let start = if g0[k] > 0.0 {
                Some((0.0, g0[k]))
            } else {
                (1..16).map(|i| i as f64 / 16.0).find_map(|s| {
                    let g = g_at(s)[k];
                    (g > 0.0).then_some((s, g))
                })
            };
            match start {
                Some((a, ga)) => {
                    let (mut a, mut b, mut ga, mut gb) = (a, 1.0, ga, g1[k]);
                    let mut side = 0i8;
                    for _ in 0..60 {
                        if b - a <= 1e-10 {
                            break;
                        }
                        let c = (a * gb - b * ga) / (gb - ga);
                        let c = if c > a && c < b { c } else { 0.5 * (a + b) };
                        let gc = g_at(c)[k];
                        if gc > 0.0 {
                            a = c;
                            ga = gc;
                            if side == -1 {
                                gb *= 0.5;
                            }
                            side = -1;
                        } else {
                            b = c;
                            gb = gc;
                            if side == 1 {
                                ga *= 0.5;
                            }
                            side = 1;
                        }
                    }
                    b
                }
                None => 1.0,
            }
        };
        if best.is_none_or(|(_, sb)| s < sb) {
            best = Some((k, s));
        }
    }
    best
}

/// The error norm: RMS of err_i / (atol + rtol max(|x₀ᵢ|, |x₁ᵢ|)) over the states that moved —
/// a state exactly 0 at both ends with no error estimate (a wheel's lift while it is on its rail,
/// the shift of a rigid track) is not counted, so that such idle states do not dilute the norm.
#[derive(Default)]
struct ErrorNorm {
    sum: f64,
    count: usize,
    /// Components added so far (idle ones included): the next one's index.
    next: usize,
    /// The largest squared term and its component.
    worst: f64,
    worst_index: Option<usize>,
}

impl ErrorNorm {
    /// Adds component `next` (components are added in order, every one of them).
    fn add(&mut self, x0: f64, x1: f64, e: f64, s: &Settings) {
        self.add_scaled(x0, x1, e, s.rtol, s.atol);
    }

    /// [`Self::add`] with the tolerances given (Radau's transformed ones).
    fn add_scaled(&mut self, x0: f64, x1: f64, e: f64, rtol: f64, atol: f64) {
        let i = self.next;
        self.next += 1;
        if x0 == 0.0 && x1 == 0.0 && e == 0.0 {
            return;
        }
        let sc = atol + rtol * x0.abs().max(x1.abs());
        let term = (e / sc).powi(2);
        self.sum += term;
        self.count += 1;
        if term > self.worst {
            self.worst = term;
            self.worst_index = Some(i);
        }
    }

    fn value(&self) -> f64 {
        (self.sum / self.count.max(1) as f64).sqrt()
    }
}

fn all_finite(v: &[f64]) -> bool {
    v.iter().all(|x| x.is_finite())
}

/// Hairer's starting step: h = 0.01 ‖x‖/‖f‖ in the weighted norm, capped.
fn initial_step(x: &[f64], f: &[f64], s: &Settings) -> f64 {
    let (mut dx, mut df) = (0.0, 0.0);
    for (xi, fi) in x.iter().zip(f) {
        let sc = s.atol + s.rtol * xi.abs();
        dx += (xi / sc).powi(2);
        df += (fi / sc).powi(2);
    }
    let n = x.len().max(1) as f64;
    let (dx, df) = ((dx / n).sqrt(), (df / n).sqrt());
    let h = if dx < 1e-5 || df < 1e-5 {
        1e-6
    } else {
        0.01 * dx / df
    };
    h.min(s.h_max).max(s.h_min * 10.0)
}

enum StepFailure<E> {
    Model(E),
    Singular,
}

struct Stepper {
    method: Method,
    k: Vec<Vec<f64>>,
    tmp: Vec<f64>,
    jac: DMatrix<f64>,
    /// ∂f/∂t at the Jacobian's point (forward difference).
    ft: Vec<f64>,
    /// Accepted steps since the Jacobian was evaluated (None: none valid).
    jac_age: Option<usize>,
    /// W-method: the system's diagonal blocks, W restricted to them ([`OdeSystem::jacobian_blocks`]).
    blocks: Option<Vec<(usize, usize)>>,
    /// The blocks by finite-difference pass (one pass per group).
    groups: Vec<Vec<(usize, usize)>>,
    /// BDF: the accepted points and the order.
    bdf: bdf::Bdf,
    /// BDF: the Newton matrix's blocks — the system's Jacobian blocks (finite differences).
    newton_blocks: Option<Vec<(usize, usize)>>,
    /// BDF: its kinematic blocks outside those (their entries the constant identity coupling, set
    /// once; solved in closed form).
    newton_kinematic: Vec<(usize, usize)>,
    /// BDF: the factored Newton matrix and the α₀ it was factored for (None after a new
    /// Jacobian).
    newton_matrix: Option<(IterationMatrix, f64)>,
    /// BDF with [`Settings::newton_reuse`]: the system's [`OdeSystem::reusable_blocks`].
    reusable: Vec<(usize, usize)>,
    /// The component with the largest error term in the last trial step ([`Stats::limiting`]).
    limiting: Option<usize>,
    /// A Rosenbrock method's tableau.
    tableau: Option<rosenbrock::Tableau>,
    /// Radau IIA: the collocation polynomial, the stages and the two factorisations.
    radau: radau::Radau,
}

impl Stepper {
    fn new(n: usize, method: Method) -> Stepper {
        Stepper {
            method,
            k: vec![vec![0.0; n]; 7],
            tmp: vec![0.0; n],
            jac: DMatrix::zeros(n, n),
            ft: vec![0.0; n],
            jac_age: None,
            blocks: None,
            groups: Vec::new(),
            bdf: bdf::Bdf::new(),
            newton_blocks: None,
            newton_kinematic: Vec::new(),
            newton_matrix: None,
            reusable: Vec::new(),
            limiting: None,
            tableau: rosenbrock::Tableau::of(method),
            radau: radau::Radau::new(if method == Method::Radau5 { n } else { 0 }),
        }
    }

    /// BDF with [`Settings::newton_reuse`]: the blocks the Newton iteration may carry forward,
    /// each checked to be one of the Newton matrix's blocks (whose Jacobian is evaluated).
    fn set_reusable(&mut self, reusable: Vec<(usize, usize)>, n: usize) -> Result<(), SettingsError> {
        let known = self.newton_blocks.as_deref().unwrap_or(&[]);
        if let Some(&(offset, size)) = reusable.iter().find(|b| !known.contains(b)) {
            return Err(SettingsError::ReusableBlock {
                offset,
                size,
                states: n,
            });
        }
        self.reusable = reusable;
        Ok(())
    }

    /// The Jacobian blocks by finite-difference group (the W-method's one group, the BDF's
    /// [`OdeSystem::newton_groups`]), checked to lie apart and within the n states, and for the
    /// BDF's Newton matrix the kinematic blocks (exact identity couplings,
    /// [`OdeSystem::kinematic_blocks`]). Without Jacobian blocks the full Jacobian is used and the
    /// kinematic blocks are not needed.
    fn set_blocks(
        &mut self,
        groups: Option<Vec<Vec<(usize, usize)>>>,
        kinematic: Vec<(usize, usize)>,
        n: usize,
    ) -> Result<(), SettingsError> {
        let Some(groups) = groups else {
            return Ok(());
        };
        let blocks: Vec<(usize, usize)> = groups.iter().flatten().copied().collect();
        let overlap = |o: usize, m: usize, skip: usize| {
            blocks
                .iter()
                .enumerate()
                .any(|(i, &(bo, bm))| i != skip && o < bo + bm && bo < o + m)
        };
        for (i, &(o, m)) in blocks.iter().enumerate() {
            if o + m > n || overlap(o, m, i) {
                return Err(SettingsError::JacobianBlock {
                    offset: o,
                    size: m,
                    states: n,
                });
            }
        }
        let mut kinematic_only = Vec::new();
        for &(o, m) in &kinematic {
            if overlap(o, m, usize::MAX) {
                continue;
            }
            if m % 2 != 0 || o + m > n {
                return Err(SettingsError::KinematicBlock {
                    offset: o,
                    size: m,
                    states: n,
                });
            }
            for i in 0..m / 2 {
                self.jac[(o + i, o + m / 2 + i)] = 1.0;
            }
            kinematic_only.push((o, m));
        }
        self.newton_blocks = Some(blocks.clone());
        self.newton_kinematic = kinematic_only;
        self.blocks = Some(blocks);
        self.groups = groups;
        Ok(())
    }

    /// The step factor after a rejection with error norm `err` (q the error's order): a BDF step
    /// whose Newton iteration failed (infinite norm) is halved; otherwise from the estimate.
    fn rejection_factor(&self, err: f64, q: f64) -> f64 {
        if self.method == Method::Radau5 {
            // Its own control: the estimate's factor, or the Newton iteration's.
            self.radau.factor
        } else if err.is_finite() {
            (0.9 * err.powf(-1.0 / q)).clamp(0.1, 0.9)
        } else if self.method == Method::Bdf && self.bdf.newton_failed {
            0.5
        } else {
            0.25
        }
    }

    /// Order q of the error estimate's exponent (h_new = h · err^(−1/q)) for the next step-size
    /// change: the BDF's varies with its order.
    fn error_order(&self) -> f64 {
        match self.method {
            Method::Dopri5 => 5.0,
            Method::Ros3 | Method::Ros34pw2 => 3.0,
            Method::Bdf => self.bdf.usable_order() as f64 + 1.0,
            // The embedded estimate's order 3.
            Method::Radau5 => 4.0,
        }
    }

    /// A step was rejected (error norm `err`, the `rejections`-th in a row at this point). The
    /// W-method's order does not depend on the Jacobian, so a mild rejection is the step size's
    /// fault; a Jacobian from an earlier point is renewed only after a rejection by a wide margin
    /// (err > 10) or a second rejection in a row.
    fn rejected(&mut self, err: f64, rejections: usize) {
        self.bdf.rejected(rejections);
        // The BDF's solution is whatever Newton converges to, whatever its matrix: a finite error
        // norm the error test rejects says nothing of the Jacobian (a Newton iteration that fails
        // with an old one renews it, `bdf_step`). The W-methods' solution depends on the matrix.
        let jacobian_blameless = matches!(self.method, Method::Bdf | Method::Radau5) && err.is_finite();
        if !jacobian_blameless && self.jac_age.is_some_and(|a| a > 0) && (err > 10.0 || rejections >= 2) {
            self.jac_age = None;
        }
    }

    /// A step was accepted: the Jacobian ages, and is renewed after `max_age` steps.
    fn accepted(&mut self, max_age: usize) {
        if let Some(a) = self.jac_age {
            self.jac_age = (a + 1 < max_age.max(1)).then_some(a + 1);
        }
    }

    /// One step of size h from (t, x) with f0 = f(t, x): x1, f1 = f(t + h, x1) and the error norm.
    #[allow(clippy::too_many_arguments)]
    fn step<S: OdeSystem + ?Sized>(
        &mut self,
        sys: &mut S,
        t: f64,
        x: &[f64],
        f0: &[f64],
        h: f64,
        s: &Settings,
        x1: &mut [f64],
        f1: &mut [f64],
        stats: &mut Stats,
    ) -> Result<f64, StepFailure<S::Error>> {
        match self.method {
            Method::Dopri5 => self.dopri5(sys, t, x, f0, h, s, x1, f1, stats),
            Method::Ros3 | Method::Ros34pw2 => {
                let tableau = self.tableau.take().expect("a Rosenbrock method has its tableau");
                let r = self.rosenbrock(&tableau, sys, t, x, f0, h, s, x1, f1, stats);
                self.tableau = Some(tableau);
                r
            }
            Method::Bdf => self.bdf_step(sys, t, x, f0, h, s, x1, f1, stats),
            Method::Radau5 => self.radau_step(sys, t, x, f0, h, s, x1, f1, stats),
        }
    }

    /// The state at t + s h (0 ≤ s ≤ 1) within the last step.
    fn dense(&self, x: &[f64], x1: &[f64], f0: &[f64], f1: &[f64], h: f64, s: f64) -> Vec<f64> {
        let s1 = 1.0 - s;
        match self.method {
            Method::Dopri5 => self.dopri5_dense(x, x1, f0, f1, h, s),
            Method::Radau5 => self.radau.dense(x1, s),
            Method::Ros3 | Method::Ros34pw2 | Method::Bdf => (0..x.len())
                .map(|i| {
                    // Cubic Hermite.
                    let (h00, h10, h01, h11) = (
                        (1.0 + 2.0 * s) * s1 * s1,
                        s * s1 * s1,
                        s * s * (3.0 - 2.0 * s),
                        -s * s * s1,
                    );
                    h00 * x[i] + h10 * h * f0[i] + h01 * x1[i] + h11 * h * f1[i]
                })
                .collect(),
        }
    }
}

pub mod bdf;
mod bdf_step;
mod dopri5;
mod jacobian;
mod newton;
mod radau;
mod rosenbrock;
use newton::IterationMatrix;
#[cfg(test)]
mod tests;
