//! The result of a work–precision sweep (`kecsim bench precision`, run by
//! [`crate::bench::precision`]): for each contact model, integrator and tolerance, the wall time
//! against the error from one reference run of the same scene, and from the rows the cost of each
//! contact model at equal error — the ratios the paper's claims rest on (KEC against the lookup
//! tables: 0.80 in the paper; KEC against online contact: ≥ 5× cheaper). Recorded by
//! [`crate::inspect::precision`].

use std::fmt::Write as _;

use crate::dynamics::integrator::Method;

/// One run of the sweep.
#[derive(Debug, Clone, PartialEq)]
pub struct PrecisionRow {
    pub contact: String,
    pub method: Method,
    pub rtol: f64,
    /// Integration wall time, s (preprocessing excluded, as in the real-time factor).
    pub wall_s: f64,
    pub preprocessing_s: f64,
    pub realtime_factor: f64,
    pub simulated_s: f64,
    pub steps: usize,
    pub rhs_evaluations: usize,
    /// `completed`, or how the run ended (`failed: …` and the like): its error then covers only
    /// the samples it has and is not used for the cost at equal error.
    pub outcome: String,
    /// Largest |Δy| (m) and |Δψ| (rad) from the reference over every wheelset and sample.
    pub max_dy: f64,
    pub max_dpsi: f64,
    /// The same up to the first real contact jump of this run or the reference
    /// ([`crate::compare::first_contact_jump`]), and that time, s: the error in single-point
    /// contact, apart from how the models treat the jumps.
    pub single_point_s: f64,
    pub single_point_max_dy: f64,
    pub single_point_max_dpsi: f64,
    /// Over the draws ([`Precision::draws`]; one draw: its own figures): the median of the
    /// draws' largest |Δy| (m) and |Δψ| (rad) — the fields above hold the largest over the draws,
    /// the wall time, steps and right-hand sides the median.
    pub median_max_dy: f64,
    pub median_max_dpsi: f64,
}

impl PrecisionRow {
    fn completed(&self) -> bool {
        self.outcome == "completed"
    }
}

/// The sweep's result.
#[derive(Debug, Clone, PartialEq)]
pub struct Precision {
    pub scene: String,
    pub simulated_s: f64,
    /// The reference run's description and its own cost.
    pub reference: String,
    pub reference_wall_s: f64,
    pub rows: Vec<PrecisionRow>,
    /// The draws: each one's initial lateral velocity of every wheelset (m/s; None: the scene's
    /// own initial state), each measured against its own reference run.
    pub draws: Vec<Option<f64>>,
}

impl Precision {
    /// The cheapest completed run of `contact` whose error is within (dy, dψ) (m, rad).
    pub fn cheapest_within(&self, contact: &str, dy: f64, dpsi: f64) -> Option<&PrecisionRow> {
        self.rows
            .iter()
            .filter(|r| r.contact == contact && r.completed() && r.max_dy <= dy && r.max_dpsi <= dpsi)
            .min_by(|a, b| a.wall_s.total_cmp(&b.wall_s))
    }

    /// Error levels (Δy m, Δψ rad) for the cost at equal error: the 0.05 mm / 0.05 mrad,
    /// the paper's 1 mm / 0.5 mrad, and between them 0.2 mm / 0.2 mrad.
    pub const LEVELS: [(f64, f64); 3] = [(0.05e-3, 0.05e-3), (0.2e-3, 0.2e-3), (1e-3, 0.5e-3)];

    /// The contact models swept, in order.
    pub fn contacts(&self) -> Vec<String> {
        let mut c: Vec<String> = Vec::new();
        for r in &self.rows {
            if !c.contains(&r.contact) {
                c.push(r.contact.clone());
            }
        }
        c
    }

    /// The report (Markdown): the rows, then the cost of each model at equal error and the
    /// ratios of the paper's claims.
    pub fn markdown(&self) -> String {
        let mut s = format!(
            "# kecsim bench precision: {}\n\n{:.2} s simulated; error = largest |Δy|, |Δψ| over every wheelset and output sample against the reference run ({}, {:.2} s wall); wall = integration time (preprocessing apart)\n\n",
            self.scene, self.simulated_s, self.reference, self.reference_wall_s
        );
        if self.draws.len() > 1 {
            let v: Vec<String> = self
                .draws
                .iter()
                .map(|d| d.map_or("the scene's".to_string(), |v| format!("{:.0}", v * 1e6)))
                .collect();
            let _ = writeln!(
                s,
                "{} draws (initial lateral velocity of every wheelset {} µm/s), each against its own reference run: the errors are the largest over the draws (and their median in the last columns), the wall time, steps and right-hand sides the median\n",
                self.draws.len(),
                v.join(", ")
            );
        }
        s += "| contact model | integrator | rtol | wall s | real-time factor | preprocessing s | steps | right-hand sides | max \\|Δy\\| [mm] | max \\|Δψ\\| [mrad] | outcome | to the first contact jump [s] | max \\|Δy\\| to it [mm] | max \\|Δψ\\| to it [mrad] | median over draws of max \\|Δy\\| [mm] | of max \\|Δψ\\| [mrad] |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
        for r in &self.rows {
            let _ = writeln!(
                s,
                "| {} | {:?} | {:.0e} | {:.3} | {:.2} | {:.2} | {} | {} | {:.4} | {:.4} | {} | {:.2} | {:.4} | {:.4} | {:.4} | {:.4} |",
                r.contact,
                r.method,
                r.rtol,
                r.wall_s,
                r.realtime_factor,
                r.preprocessing_s,
                r.steps,
                r.rhs_evaluations,
                r.max_dy * 1e3,
                r.max_dpsi * 1e3,
                r.outcome,
                r.single_point_s,
                r.single_point_max_dy * 1e3,
                r.single_point_max_dpsi * 1e3,
                r.median_max_dy * 1e3,
                r.median_max_dpsi * 1e3
            );
        }
        let contacts = self.contacts();
        s += "\nCost at equal error: the wall time of each contact model's cheapest completed run within the error level (— : no run of the sweep reaches it).\n\n| error level |";
        for c in &contacts {
            let _ = write!(s, " {c} |");
        }
        s += " kec / lookup | kec / lookup2 | online / kec |\n|---|";
        s += &"---|".repeat(contacts.len() + 3);
        s += "\n";
        for (dy, dpsi) in Self::LEVELS {
            let _ = write!(s, "| {} mm, {} mrad |", dy * 1e3, dpsi * 1e3);
            for c in &contacts {
                match self.cheapest_within(c, dy, dpsi) {
                    Some(r) => {
                        let _ = write!(s, " {:.3} s ({:?} {:.0e}) |", r.wall_s, r.method, r.rtol);
                    }
                    None => s += " — |",
                }
            }
            let ratio = |a: &str, b: &str| match (
                self.cheapest_within(a, dy, dpsi),
                self.cheapest_within(b, dy, dpsi),
            ) {
                (Some(x), Some(y)) if y.wall_s > 0.0 => format!("{:.2}", x.wall_s / y.wall_s),
                _ => "—".to_string(),
            };
            let _ = writeln!(
                s,
                " {} | {} | {} |",
                ratio("kec", "lookup"),
                ratio("kec", "lookup2"),
                ratio("online", "kec")
            );
        }
        s += "\nThe paper's claims: KEC costs 0.80 of the lookup tables (kec / lookup < 1), and online contact at least 5× KEC (online / kec ≥ 5).\n";
        s
    }
}
