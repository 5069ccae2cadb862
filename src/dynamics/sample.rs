//! The output sample of one wheelset ([`Sample`]) and the **table of what a run records of it**
//! ([`QUANTITIES`]): each recorded quantity declared once, with its value in the sample, its CSV
//! column(s) and its series in the recording. Everything that lists the quantities is generated
//! from the table:
//!
//! * the CSV header and rows of `kecsim run --csv` ([`crate::dynamics::output::CSV_COLUMNS`],
//!   [`crate::dynamics::output::csv_row`]);
//! * the recording's series under `run/NAME/` and `run/vehicle/`, their line names and styles,
//!   and the panels of the run's layout ([`crate::inspect::run`]).
//!
//! To record a new quantity: compute it in [`Sample::new`] (a field of [`Sample`]) and add one
//! [`Quantity`] to [`QUANTITIES`]. The CSV columns, series entities and titles are made of the
//! table's stems and [`Unit`]s; the tests pin today's names (`kecsim run --csv`'s columns and the
//! recording's entity paths are interfaces that scripts rely on).
//!
//! This module depends on nothing of the run's output (CSV, summary, safety): they depend on it.

use std::ops::Deref;

use super::system::WheelsetSample;

/// EN 14363's sliding window along the track for Y/Q, ΣY (and here the wear number's mean), m.
pub const WINDOW_M: f64 = 2.0;

/// One output sample of one wheelset.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample {
    pub t: f64,
    /// Arc length of the wheelset, m.
    pub s: f64,
    /// The wheelset's forward speed along the track, ṡ = V + ẋ, m/s.
    pub speed: f64,
    /// The reference's speed V (the scene's V(t)), m/s.
    pub reference_speed: f64,
    /// The drive's torque on each wheel (left, right), N m ([`super::traction`]).
    pub drive_torque: [f64; 2],
    /// The vehicle's traction (the drive's force and the ties' to the track frame), N: the same
    /// in every wheelset's sample ([`Sample::with_traction`]).
    pub traction: f64,
    /// The vehicle's traction power at the wheels, W (as `traction`).
    pub traction_power: f64,
    /// The vehicle's speed along the track, its centre of mass's (the masses' mean ṡ), m/s (as
    /// `traction`).
    pub vehicle_speed: f64,
    pub y: f64,
    pub yaw: f64,
    /// Centre height minus r0, m.
    pub z: f64,
    pub roll: f64,
    /// Normal forces left, right, N.
    pub normal: [f64; 2],
    /// Creep forces (contact frame) left, right: Fx, Fy, N.
    pub creep_x: [f64; 2],
    pub creep_y: [f64; 2],
    /// Lateral (Y) and vertical (Q) wheel–rail force on each wheel, track frame, N.
    pub y_force: [f64; 2],
    pub q_force: [f64; 2],
    /// Contact on the real wheel and rail (paper convention), m.
    pub s_wheel: [f64; 2],
    pub s_rail: [f64; 2],
    /// Contact positions (Y, Z) in the wheelset-track frame, m.
    pub position: [(f64, f64); 2],
    /// KEC: knife-edge contact parameters, m.
    pub s_knife: Option<[f64; 2]>,
    /// Rail irregularities at the wheelset: left (Y, Z), right (Y, Z), m.
    pub rails: [f64; 4],
    /// Each wheel's gap to its rail (0 on the rail; a lifted wheel's lift), m.
    pub lift: [f64; 2],
    /// Lateral shift of the track under the wheelset (0 on a rigid track), m.
    pub track_shift: f64,
    /// Creepages left, right: ξx, ξy (dimensionless), spin φ (1/m).
    pub creepage: [[f64; 3]; 2],
    /// Semi-axes (a, b) of each wheel's contact ellipse, m (0 for a lifted wheel).
    pub semi_axes: [[f64; 2]; 2],
    /// Each wheel's creep moment Mz about the contact normal, N m (0 where the creep model
    /// defines none: Polach, the linear model).
    pub spin_moment: [f64; 2],
    /// Each wheel's wear number Tγ ([`Self::wear_number`]) as its mean over the last 2 m of
    /// track up to this sample (EN 14363's window, as Y/Q's), N: set by the run from the samples
    /// before it ([`Sample::set_wear_number_2m`]); over the first 2 m, the mean of what there is.
    pub tgamma_2m: [f64; 2],
    /// Each wheel's maximum contact pressure from the patch model valid at its contact, Pa: Hertz's
    /// p0 where Hertz holds, the strip model's pmax where it does not (0: not assessed — a run
    /// without the profiles; [`Self::contact_pressure`] then falls back to Hertz).
    pub pmax: [f64; 2],
    /// Each wheel's contact area from the same model, m² (0: not assessed).
    pub contact_area: [f64; 2],
    /// Hertz's gap deviation D at each wheel's contact
    /// (`crate::contact::nonhertz::validity`; NaN: not assessed, off the rail).
    pub hertz_deviation: [f64; 2],
    /// Patches the strip model found at each wheel (0 where Hertz holds or not assessed).
    pub patches: [u8; 2],
}

impl Sample {
    /// The output sample of one wheelset evaluation (Y and Q per wheel in the track frame).
    pub fn new(t: f64, s: &WheelsetSample, r0: f64) -> Sample {
        let d = &s.dynamics;
        let y_force = [d.wheel_force[0].0, d.wheel_force[1].0];
        let q_force = [d.wheel_force[0].1, d.wheel_force[1].1];
        Sample {
            t,
            s: s.s,
            speed: s.speed,
            reference_speed: s.reference_speed,
            drive_torque: s.drive_torque,
            traction: 0.0,
            traction_power: 0.0,
            vehicle_speed: s.speed,
            y: s.state.y,
            yaw: s.state.psi,
            z: s.kin.z - r0,
            roll: s.kin.phi,
            normal: d.normal,
            creep_x: [d.creep[0].fx, d.creep[1].fx],
            creep_y: [d.creep[0].fy, d.creep[1].fy],
            y_force,
            q_force,
            s_wheel: [s.kin.contacts[0].s_wheel, s.kin.contacts[1].s_wheel],
            s_rail: [s.kin.contacts[0].s_rail, s.kin.contacts[1].s_rail],
            position: [s.kin.contacts[0].position, s.kin.contacts[1].position],
            s_knife: s.kin.s_knife,
            rails: s.rails,
            lift: d.lift_gap,
            track_shift: s.state.track_shift,
            creepage: d.creepage.map(|c| [c.longitudinal, c.lateral, c.spin]),
            semi_axes: d.semi_axes.map(|(a, b)| [a, b]),
            spin_moment: [d.creep[0].mz, d.creep[1].mz],
            tgamma_2m: [0.0; 2],
            pmax: [0.0; 2],
            contact_area: [0.0; 2],
            hertz_deviation: [f64::NAN; 2],
            patches: [0; 2],
        }
    }

    /// Each wheel's maximum contact pressure from the model valid at its contact ([`Self::pmax`]),
    /// Hertz's p0 where none was assessed, Pa (0 for a lifted wheel).
    pub fn contact_pressure(&self) -> [f64; 2] {
        let hertz = self.max_pressure();
        [0, 1].map(|i| {
            if self.normal[i] <= 0.0 {
                0.0
            } else if self.pmax[i] > 0.0 {
                self.pmax[i]
            } else {
                hertz[i]
            }
        })
    }

    /// Each wheel's contact area ([`Self::contact_area`]), the Hertz ellipse's πab where none was
    /// assessed, m².
    pub fn patch_area(&self) -> [f64; 2] {
        [0, 1].map(|i| {
            if self.contact_area[i] > 0.0 {
                self.contact_area[i]
            } else {
                let [a, b] = self.semi_axes[i];
                std::f64::consts::PI * a * b
            }
        })
    }

    /// The sample with the vehicle's traction (force and power) and speed of its evaluation.
    pub fn with_traction(mut self, traction: &super::traction::TractionState) -> Sample {
        self.traction = traction.traction_n();
        self.traction_power = traction.power_w;
        self.vehicle_speed = traction.speed_m_s;
        self
    }

    /// Sets [`Self::tgamma_2m`] from the samples before this one (in order of arc length): the
    /// mean of Tγ over those within 2 m behind it and itself.
    pub fn set_wear_number_2m(&mut self, before: &[Sample]) {
        let mut sum = self.wear_number();
        let mut n = 1.0;
        for p in before.iter().rev() {
            if self.s - p.s >= WINDOW_M {
                break;
            }
            let w = p.wear_number();
            sum = [sum[0] + w[0], sum[1] + w[1]];
            n += 1.0;
        }
        self.tgamma_2m = sum.map(|x| x / n);
    }

    /// Each wheel's maximum Hertz pressure p0 = 3N / (2π a b), Pa (Johnson, *Contact Mechanics*,
    /// Eq. 4.29; 0 for a lifted wheel).
    pub fn max_pressure(&self) -> [f64; 2] {
        [0, 1].map(|i| {
            let [a, b] = self.semi_axes[i];
            if a > 0.0 && b > 0.0 && self.normal[i] > 0.0 {
                3.0 * self.normal[i] / (2.0 * std::f64::consts::PI * a * b)
            } else {
                0.0
            }
        })
    }

    /// Each wheel's wear number Tγ = |Fx ξx + Fy ξy|, N: the creep forces' work per distance
    /// rolled (the energy dissipated in the patch per metre), without the spin term
    /// ([`Self::wear_number_spin`]).
    pub fn wear_number(&self) -> [f64; 2] {
        [0, 1].map(|i| (self.creep_x[i] * self.creepage[i][0] + self.creep_y[i] * self.creepage[i][1]).abs())
    }

    /// Each wheel's spin term of the wear number, |Mz φ|, N (0 where the creep model defines no
    /// spin moment).
    pub fn wear_number_spin(&self) -> [f64; 2] {
        [0, 1].map(|i| (self.spin_moment[i] * self.creepage[i][2]).abs())
    }

    /// The larger |Y/Q| of the two wheels (a lifted wheel, Q = 0, has none).
    pub fn max_abs_y_over_q(&self) -> f64 {
        let ratio = |i: usize| {
            if self.q_force[i] > 0.0 {
                (self.y_force[i] / self.q_force[i]).abs()
            } else {
                0.0
            }
        };
        ratio(0).max(ratio(1))
    }
}

/// The unit a quantity is written or recorded in: the suffix of its CSV column and series entity,
/// the label of its plot, and its factor from the sample's SI value.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Unit {
    /// The end of the names: `y_mm`, `normal_kn`, `speed_m_s` (empty for a ratio: `y_over_q`).
    pub suffix: &'static str,
    /// In plot titles: `y [mm]` (empty for a ratio: `Y/Q`).
    pub label: &'static str,
    /// The value in this unit of one SI unit.
    pub per_si: f64,
}

impl Unit {
    pub const S: Unit = Unit::new("s", "s", 1.0);
    pub const M: Unit = Unit::new("m", "m", 1.0);
    pub const M_S: Unit = Unit::new("m_s", "m/s", 1.0);
    pub const MM: Unit = Unit::new("mm", "mm", 1e3);
    pub const MRAD: Unit = Unit::new("mrad", "mrad", 1e3);
    pub const N: Unit = Unit::new("n", "N", 1.0);
    pub const KN: Unit = Unit::new("kn", "kN", 1e-3);
    /// A ratio (no unit).
    pub const RATIO: Unit = Unit::new("", "", 1.0);
    /// Per metre (spin creepage).
    pub const PER_M: Unit = Unit::new("1pm", "1/m", 1.0);
    /// Megapascal (contact pressure).
    pub const MPA: Unit = Unit::new("mpa", "MPa", 1e-6);
    /// Newton metre (torque).
    pub const N_M: Unit = Unit::new("n_m", "N m", 1.0);
    /// Kilowatt (power).
    pub const KW: Unit = Unit::new("kw", "kW", 1e-3);
    /// Square millimetre (contact area).
    pub const MM2: Unit = Unit::new("mm2", "mm²", 1e6);

    const fn new(suffix: &'static str, label: &'static str, per_si: f64) -> Unit {
        Unit {
            suffix,
            label,
            per_si,
        }
    }

    /// `STEM_SUFFIX` (the stem alone for a ratio).
    pub fn name(self, stem: &str) -> String {
        if self.suffix.is_empty() {
            stem.to_string()
        } else {
            format!("{stem}_{}", self.suffix)
        }
    }

    /// `TITLE [LABEL]` (the title alone for a ratio).
    pub fn title(self, title: &str) -> String {
        if self.label.is_empty() {
            title.to_string()
        } else {
            format!("{title} [{}]", self.label)
        }
    }
}

/// The wheels of a per-wheel quantity, in the order of its values (and its CSV columns' infix).
pub const WHEELS: [&str; 2] = ["left", "right"];

/// A quantity's values in a sample, SI: how many and how they are read.
#[derive(Debug, Clone, Copy)]
pub enum Value {
    /// One value.
    One(fn(&Sample) -> f64),
    /// One per wheel (left, right).
    Wheels(fn(&Sample) -> [f64; 2]),
    /// One per wheel where the contact model gives them (KEC's knife-edge parameters): a sample
    /// without them writes NaN to the CSV, and the recording sends the series only for batches
    /// where every sample has them.
    WheelsWhereGiven(fn(&Sample) -> Option<[f64; 2]>),
}

/// The values of a quantity in a sample (one, or one per wheel), in some [`Unit`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Values {
    values: [f64; 2],
    len: usize,
}

impl Deref for Values {
    type Target = [f64];
    fn deref(&self) -> &[f64] {
        &self.values[..self.len]
    }
}

impl Value {
    /// How many values a sample has of it: 1, or 2 (one per wheel).
    pub fn width(self) -> usize {
        match self {
            Value::One(_) => 1,
            Value::Wheels(_) | Value::WheelsWhereGiven(_) => 2,
        }
    }

    /// Whether some samples lack it ([`Value::WheelsWhereGiven`]).
    pub fn is_conditional(self) -> bool {
        matches!(self, Value::WheelsWhereGiven(_))
    }

    /// Its values in `s`, in `unit` (None where the sample has none).
    pub fn of(self, s: &Sample, unit: Unit) -> Option<Values> {
        let (values, len) = match self {
            Value::One(f) => ([f(s), 0.0], 1),
            Value::Wheels(f) => (f(s), 2),
            Value::WheelsWhereGiven(f) => (f(s)?, 2),
        };
        Some(Values {
            values: values.map(|v| v * unit.per_si),
            len,
        })
    }
}

/// Where a quantity goes in the CSV of a wheelset (`kecsim run --csv`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Csv {
    /// Not written.
    No,
    /// Its column(s) after the previous quantity's: `STEM_UNIT` (one value) or `STEM_left_UNIT`,
    /// `STEM_right_UNIT` (one per wheel).
    Columns(&'static str, Unit),
    /// One per wheel, written wheel by wheel together with the previous quantity in the CSV
    /// (itself per wheel): `fx_left_n, fy_left_n, fx_right_n, fy_right_n`.
    WheelByWheelWithPrevious(&'static str, Unit),
}

/// A row of plots in the run's layout (top to bottom in the order of [`Panel::ALL`]); a panel's
/// plots are in the order of [`QUANTITIES`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Panel {
    /// Displacements and rotations.
    Kinematics,
    /// Wheel–rail forces.
    Forces,
    /// Where the wheels touch the rails.
    Contact,
    /// Contact stress and wear.
    Wear,
}

impl Panel {
    pub const ALL: [Panel; 4] = [Panel::Kinematics, Panel::Forces, Panel::Contact, Panel::Wear];
}

/// A quantity's series in the recording.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Series {
    /// The entity's name before its unit: `creep_fx` records `run/NAME/creep_fx_kn`.
    pub stem: &'static str,
    pub unit: Unit,
    /// Its plot's title before the unit (`creep Fx` shows as `w1: creep Fx [kN]`); the line's
    /// name of a one-value series (a per-wheel one has `left` and `right`).
    pub title: &'static str,
    /// Recorded for every wheelset under `run/NAME/`, and the first wheelset's plotted in this
    /// panel (None: not recorded per wheelset).
    pub panel: Option<Panel>,
    /// Recorded under `run/vehicle/` too, one line per wheelset, and plotted in the layout's
    /// every-wheelset row, when the vehicle has more than one wheelset (one-value quantities).
    pub vehicle: bool,
    /// The vehicle's own quantity, the same in every wheelset's sample (its traction): recorded
    /// once, under `run/vehicle/`, from the first wheelset's samples, and plotted in the layout's
    /// every-wheelset row whatever the number of wheelsets (one-value quantities).
    pub once: bool,
}

impl Series {
    /// Its entity's name under `run/NAME/` or `run/vehicle/` (`creep_fx_kn`).
    pub fn entity(&self) -> String {
        self.unit.name(self.stem)
    }

    /// Its plot's title without the wheelset (`creep Fx [kN]`).
    pub fn title(&self) -> String {
        self.unit.title(self.title)
    }
}

/// One quantity a run records of each wheelset's samples: declared once in [`QUANTITIES`].
#[derive(Debug, Clone, Copy)]
pub struct Quantity {
    /// What it is (documentation, and the name tests report).
    pub name: &'static str,
    /// Its values in a sample (SI).
    pub value: Value,
    /// Its CSV column(s).
    pub csv: Csv,
    /// Its series in the recording (None: not recorded as a series).
    pub series: Option<Series>,
}

/// A series plotted in `panel` for every wheelset, not under `run/vehicle/`.
const fn plot(stem: &'static str, unit: Unit, title: &'static str, panel: Panel) -> Option<Series> {
    Some(Series {
        stem,
        unit,
        title,
        panel: Some(panel),
        vehicle: false,
        once: false,
    })
}

/// A vehicle's own series ([`Series::once`]): recorded once under `run/vehicle/`.
const fn vehicle_own(stem: &'static str, unit: Unit, title: &'static str) -> Option<Series> {
    Some(Series {
        stem,
        unit,
        title,
        panel: None,
        vehicle: false,
        once: true,
    })
}

/// **What a run records of each wheelset**, in the order of the CSV's columns and of the layout's
/// plots: the one place a recorded quantity is declared (see the module's documentation). The CSV
/// columns and series names it makes are interfaces: [`crate::dynamics::output`]'s and
/// [`crate::inspect::run`]'s tests pin them.
pub const QUANTITIES: &[Quantity] = &[
    Quantity {
        name: "time",
        value: Value::One(|s| s.t),
        csv: Csv::Columns("t", Unit::S),
        series: None,
    },
    Quantity {
        name: "arc length of the wheelset",
        value: Value::One(|s| s.s),
        csv: Csv::Columns("s", Unit::M),
        series: None,
    },
    Quantity {
        name: "forward speed along the track (ṡ = V + ẋ)",
        value: Value::One(|s| s.speed),
        csv: Csv::Columns("speed", Unit::M_S),
        // (Recorded as the vehicle's own speed, `vehicle_speed`: the wheelsets' differ from it by
        // their millimetre swings on the suspension.)
        series: None,
    },
    Quantity {
        name: "lateral displacement",
        value: Value::One(|s| s.y),
        csv: Csv::Columns("y", Unit::MM),
        series: Some(Series {
            stem: "y",
            unit: Unit::MM,
            title: "y",
            panel: Some(Panel::Kinematics),
            vehicle: true,
            once: false,
        }),
    },
    Quantity {
        name: "yaw angle",
        value: Value::One(|s| s.yaw),
        csv: Csv::Columns("yaw", Unit::MRAD),
        series: Some(Series {
            stem: "yaw",
            unit: Unit::MRAD,
            title: "yaw",
            panel: Some(Panel::Kinematics),
            vehicle: true,
            once: false,
        }),
    },
    Quantity {
        name: "centre height minus r0",
        value: Value::One(|s| s.z),
        csv: Csv::Columns("z", Unit::MM),
        series: plot("z", Unit::MM, "z − r0", Panel::Kinematics),
    },
    Quantity {
        name: "roll angle",
        value: Value::One(|s| s.roll),
        csv: Csv::Columns("roll", Unit::MRAD),
        series: plot("roll", Unit::MRAD, "roll", Panel::Kinematics),
    },
    Quantity {
        name: "normal force (constraint reaction, Eq. 53)",
        value: Value::Wheels(|s| s.normal),
        csv: Csv::Columns("n", Unit::N),
        series: plot("normal", Unit::KN, "normal force", Panel::Forces),
    },
    Quantity {
        name: "creep force Fx, contact frame",
        value: Value::Wheels(|s| s.creep_x),
        csv: Csv::Columns("fx", Unit::N),
        series: plot("creep_fx", Unit::KN, "creep Fx", Panel::Forces),
    },
    Quantity {
        name: "creep force Fy, contact frame",
        value: Value::Wheels(|s| s.creep_y),
        csv: Csv::WheelByWheelWithPrevious("fy", Unit::N),
        series: plot("creep_fy", Unit::KN, "creep Fy", Panel::Forces),
    },
    Quantity {
        name: "lateral wheel–rail force Y, track frame",
        value: Value::Wheels(|s| s.y_force),
        csv: Csv::Columns("y", Unit::N),
        series: None,
    },
    Quantity {
        name: "vertical wheel–rail force Q, track frame",
        value: Value::Wheels(|s| s.q_force),
        csv: Csv::WheelByWheelWithPrevious("q", Unit::N),
        series: None,
    },
    Quantity {
        name: "lateral over vertical wheel–rail force Y/Q",
        value: Value::Wheels(|s| [s.y_force[0] / s.q_force[0], s.y_force[1] / s.q_force[1]]),
        csv: Csv::No,
        series: plot("y_over_q", Unit::RATIO, "Y/Q", Panel::Forces),
    },
    Quantity {
        name: "contact position on the real wheel s^w",
        value: Value::Wheels(|s| s.s_wheel),
        csv: Csv::Columns("s_wheel", Unit::MM),
        series: plot("s_wheel", Unit::MM, "contact on wheel s^w", Panel::Contact),
    },
    Quantity {
        name: "contact position on the real rail s^r",
        value: Value::Wheels(|s| s.s_rail),
        csv: Csv::WheelByWheelWithPrevious("s_rail", Unit::MM),
        series: plot("s_rail", Unit::MM, "contact on rail s^r", Panel::Contact),
    },
    Quantity {
        name: "KEC contact on the equivalent profiles s^k (KEC only)",
        value: Value::WheelsWhereGiven(|s| s.s_knife),
        csv: Csv::No,
        series: plot("s_knife", Unit::MM, "KEC contact s^k", Panel::Contact),
    },
    Quantity {
        name: "lateral rail irregularity",
        value: Value::Wheels(|s| [s.rails[0], s.rails[2]]),
        csv: Csv::Columns("rail_y", Unit::MM),
        series: None,
    },
    Quantity {
        name: "vertical rail irregularity",
        value: Value::Wheels(|s| [s.rails[1], s.rails[3]]),
        csv: Csv::WheelByWheelWithPrevious("rail_z", Unit::MM),
        series: None,
    },
    Quantity {
        name: "wheel lift (each wheel's gap to its rail; 0 on it)",
        value: Value::Wheels(|s| s.lift),
        csv: Csv::Columns("lift", Unit::MM),
        series: plot("lift", Unit::MM, "wheel lift", Panel::Contact),
    },
    Quantity {
        name: "lateral track shift under the wheelset",
        value: Value::One(|s| s.track_shift),
        csv: Csv::Columns("track_shift", Unit::MM),
        series: None,
    },
    Quantity {
        name: "longitudinal creepage ξx",
        value: Value::Wheels(|s| [s.creepage[0][0], s.creepage[1][0]]),
        csv: Csv::Columns("creep_x", Unit::RATIO),
        series: None,
    },
    Quantity {
        name: "lateral creepage ξy",
        value: Value::Wheels(|s| [s.creepage[0][1], s.creepage[1][1]]),
        csv: Csv::Columns("creep_y", Unit::RATIO),
        series: None,
    },
    Quantity {
        name: "spin creepage φ",
        value: Value::Wheels(|s| [s.creepage[0][2], s.creepage[1][2]]),
        csv: Csv::Columns("spin", Unit::PER_M),
        series: None,
    },
    Quantity {
        name: "contact ellipse semi-axis a (rolling direction)",
        value: Value::Wheels(|s| [s.semi_axes[0][0], s.semi_axes[1][0]]),
        csv: Csv::Columns("a", Unit::MM),
        series: None,
    },
    Quantity {
        name: "contact ellipse semi-axis b (lateral)",
        value: Value::Wheels(|s| [s.semi_axes[0][1], s.semi_axes[1][1]]),
        csv: Csv::Columns("b", Unit::MM),
        series: None,
    },
    Quantity {
        name: "maximum Hertz pressure p0",
        value: Value::Wheels(Sample::max_pressure),
        csv: Csv::Columns("p0", Unit::MPA),
        series: plot("p0", Unit::MPA, "max. Hertz pressure p0", Panel::Wear),
    },
    Quantity {
        name: "wear number Tγ = |Fx ξx + Fy ξy|",
        value: Value::Wheels(Sample::wear_number),
        csv: Csv::Columns("tgamma", Unit::N),
        series: plot("tgamma", Unit::N, "wear number Tγ", Panel::Wear),
    },
    Quantity {
        name: "the wear number's spin term |Mz φ|",
        value: Value::Wheels(Sample::wear_number_spin),
        csv: Csv::Columns("tgamma_spin", Unit::N),
        series: None,
    },
    Quantity {
        name: "the wear number's 2 m sliding mean",
        value: Value::Wheels(|s| s.tgamma_2m),
        csv: Csv::Columns("tgamma_2m", Unit::N),
        series: plot("tgamma_2m", Unit::N, "wear number Tγ, 2 m mean", Panel::Wear),
    },
    Quantity {
        name: "the smaller wheel load",
        value: Value::One(|s| s.normal[0].min(s.normal[1])),
        csv: Csv::No,
        series: Some(Series {
            stem: "min_normal",
            unit: Unit::KN,
            title: "smaller wheel load",
            panel: None,
            vehicle: true,
            once: false,
        }),
    },
    Quantity {
        name: "the larger |Y/Q| of the two wheels",
        value: Value::One(Sample::max_abs_y_over_q),
        csv: Csv::No,
        series: Some(Series {
            stem: "max_abs_y_over_q",
            unit: Unit::RATIO,
            title: "larger |Y/Q|",
            panel: None,
            vehicle: true,
            once: false,
        }),
    },
    // Issue 46: the speed held and what it took (appended: the columns before keep their places).
    Quantity {
        name: "the reference's speed V",
        value: Value::One(|s| s.reference_speed),
        csv: Csv::Columns("reference_speed", Unit::M_S),
        series: None,
    },
    Quantity {
        name: "the vehicle's speed along the track (its centre of mass's)",
        value: Value::One(|s| s.vehicle_speed),
        csv: Csv::Columns("vehicle_speed", Unit::M_S),
        series: vehicle_own("vehicle_speed", Unit::M_S, "speed (centre of mass)"),
    },
    Quantity {
        name: "the drive's torque on each wheel",
        value: Value::Wheels(|s| s.drive_torque),
        csv: Csv::Columns("drive_torque", Unit::N_M),
        series: None,
    },
    Quantity {
        name: "the vehicle's traction (drive and ties)",
        value: Value::One(|s| s.traction),
        csv: Csv::Columns("traction", Unit::N),
        series: vehicle_own("traction", Unit::KN, "traction"),
    },
    Quantity {
        name: "the vehicle's traction power at the wheels",
        value: Value::One(|s| s.traction_power),
        csv: Csv::Columns("traction_power", Unit::KW),
        series: vehicle_own("traction_power", Unit::KW, "traction power"),
    },
    // Issue 49: the patch beyond Hertz (appended: the columns before keep their places).
    Quantity {
        name: "maximum contact pressure (Hertz where valid, else the strip model)",
        value: Value::Wheels(Sample::contact_pressure),
        csv: Csv::Columns("pmax", Unit::MPA),
        series: plot(
            "pmax",
            Unit::MPA,
            "max. contact pressure (valid model)",
            Panel::Wear,
        ),
    },
    Quantity {
        name: "contact area (Hertz where valid, else the strip model)",
        value: Value::Wheels(Sample::patch_area),
        csv: Csv::Columns("contact_area", Unit::MM2),
        series: None,
    },
    Quantity {
        name: "Hertz's gap deviation D over its patch",
        value: Value::Wheels(|s| s.hertz_deviation),
        csv: Csv::Columns("hertz_dev", Unit::RATIO),
        series: None,
    },
    Quantity {
        name: "patches of the strip model",
        value: Value::Wheels(|s| s.patches.map(f64::from)),
        csv: Csv::Columns("patches", Unit::RATIO),
        series: None,
    },
];

#[cfg(test)]
impl Sample {
    /// A centred wheelset at time `t`, arc length `s` and speed `speed`, every other field zero
    /// (for tests that build their own samples).
    pub(crate) fn at(t: f64, s: f64, speed: f64) -> Sample {
        Sample {
            t,
            s,
            speed,
            reference_speed: speed,
            drive_torque: [0.0; 2],
            traction: 0.0,
            traction_power: 0.0,
            vehicle_speed: speed,
            y: 0.0,
            yaw: 0.0,
            z: 0.0,
            roll: 0.0,
            normal: [0.0; 2],
            creep_x: [0.0; 2],
            creep_y: [0.0; 2],
            y_force: [0.0; 2],
            q_force: [0.0; 2],
            s_wheel: [0.0; 2],
            s_rail: [0.0; 2],
            position: [(0.0, 0.0); 2],
            s_knife: None,
            rails: [0.0; 4],
            lift: [0.0; 2],
            track_shift: 0.0,
            creepage: [[0.0; 3]; 2],
            semi_axes: [[0.0; 2]; 2],
            spin_moment: [0.0; 2],
            tgamma_2m: [0.0; 2],
            pmax: [0.0; 2],
            contact_area: [0.0; 2],
            hertz_deviation: [f64::NAN; 2],
            patches: [0; 2],
        }
    }

    /// A sample whose every field has a value of its own.
    pub(crate) fn distinct() -> Sample {
        Sample {
            t: 1.5,
            s: 23.25,
            speed: 19.0,
            reference_speed: 19.25,
            drive_torque: [55.0, 65.0],
            traction: 450.0,
            traction_power: 8550.0,
            vehicle_speed: 19.125,
            y: 0.002,
            yaw: -0.0015,
            z: 0.0007,
            roll: 0.0003,
            normal: [48e3, 52e3],
            creep_x: [-1.5e3, 2.5e3],
            creep_y: [3.5e3, -4.5e3],
            y_force: [6e3, -8e3],
            q_force: [40e3, 50e3],
            s_wheel: [0.004, -0.005],
            s_rail: [0.006, -0.007],
            position: [(0.75, 0.01), (-0.74, 0.02)],
            s_knife: Some([0.0085, -0.0095]),
            rails: [0.75, 0.001, -0.75, 0.002],
            lift: [0.0, 0.0125],
            track_shift: 0.0005,
            creepage: [[1.1e-3, -2.1e-3, 0.31], [-1.3e-3, 2.3e-3, -0.37]],
            semi_axes: [[6.1e-3, 4.1e-3], [7.1e-3, 3.1e-3]],
            spin_moment: [11.0, -13.0],
            tgamma_2m: [7.5, 12.5],
            pmax: [1.2e9, 0.9e9],
            contact_area: [80e-6, 70e-6],
            hertz_deviation: [0.125, 0.5],
            patches: [1, 2],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The table is well formed: a quantity written wheel by wheel with the previous one is, like
    /// that one, per wheel; every-wheelset series have one value per sample (a line per wheelset)
    /// that every sample has; names are made of stems without a unit.
    #[test]
    fn the_table_is_well_formed() {
        let mut previous_csv: Option<&Quantity> = None;
        for q in QUANTITIES {
            if let Csv::WheelByWheelWithPrevious(..) = q.csv {
                let p = previous_csv.expect("a first CSV quantity written with a previous one");
                assert!(q.value.width() == 2 && p.value.width() == 2, "{}", q.name);
            }
            if q.csv != Csv::No {
                previous_csv = Some(q);
            }
            if let Some(s) = q.series {
                assert!(
                    s.panel.is_some() || s.vehicle || s.once,
                    "{}: recorded nowhere",
                    q.name
                );
                assert!(
                    !(s.once && (s.vehicle || s.panel.is_some())),
                    "{}: a vehicle's own quantity is recorded once",
                    q.name
                );
                if s.vehicle || s.once {
                    assert!(q.value.width() == 1 && !q.value.is_conditional(), "{}", q.name);
                }
                assert!(!s.stem.ends_with(&format!("_{}", s.unit.suffix)), "{}", q.name);
            }
            let v = q.value.of(&Sample::distinct(), Unit::RATIO).unwrap();
            assert_eq!(v.len(), q.value.width(), "{}", q.name);
        }
    }
}
