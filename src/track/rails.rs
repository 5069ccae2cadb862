//! The rails at one cross-section of the track: its two sides, where the gauge is measured, and the rail
//! displacements that the irregularities make of the ideal rails (METHOD.md §2, Eq. 5–11) — what
//! the contact models see of the track.

/// Side of the track. Left is +Y (track frame Y to the left, paper §2.2).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Side {
    Left,
    Right,
}

impl Side {
    pub const BOTH: [Side; 2] = [Side::Left, Side::Right];

    /// +1 on the left, −1 on the right.
    pub fn sign(self) -> f64 {
        match self {
            Side::Left => 1.0,
            Side::Right => -1.0,
        }
    }

    /// `"left"` / `"right"`, as used in entity paths and CSV columns.
    pub fn name(self) -> &'static str {
        match self {
            Side::Left => "left",
            Side::Right => "right",
        }
    }
}

/// Track gauge and where it is measured.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrackGauge {
    /// Distance between the gauge points, m (1.435 standard gauge).
    pub gauge_m: f64,
    /// Depth below the running surface within which the gauge point is sought, m (0.014).
    pub measuring_depth_m: f64,
}

impl Default for TrackGauge {
    fn default() -> Self {
        TrackGauge {
            gauge_m: 1.435,
            measuring_depth_m: 0.014,
        }
    }
}

/// Rail profile-frame displacements at a wheelset's cross-section: the irregularities of
/// METHOD.md §2 (Eq. 5–11) as the contact geometry sees them.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct RailOffsets {
    /// Lateral displacement of the left rail, y_lir, m.
    pub y_left: f64,
    /// Vertical displacement of the left rail, z_lir, m.
    pub z_left: f64,
    /// Lateral displacement of the right rail, y_rir, m.
    pub y_right: f64,
    /// Vertical displacement of the right rail, z_rir, m.
    pub z_right: f64,
}

impl RailOffsets {
    /// From the industry combinations: alignment, vertical profile, gauge variation, cross level
    /// (al = (y_l + y_r)/2, vp = (z_l + z_r)/2, gv = y_l − y_r, cl = z_l − z_r), m.
    pub fn from_irregularities(al: f64, vp: f64, gv: f64, cl: f64) -> Self {
        RailOffsets {
            y_left: al + 0.5 * gv,
            y_right: al - 0.5 * gv,
            z_left: vp + 0.5 * cl,
            z_right: vp - 0.5 * cl,
        }
    }

    /// Gauge variation only (rails moved apart symmetrically by gv/2 each).
    pub fn gauge_variation(gv: f64) -> Self {
        Self::from_irregularities(0.0, 0.0, gv, 0.0)
    }

    /// From q_r = [y_lir, z_lir, y_rir, z_rir].
    pub fn from_array(q: [f64; 4]) -> Self {
        RailOffsets {
            y_left: q[0],
            z_left: q[1],
            y_right: q[2],
            z_right: q[3],
        }
    }

    /// q_r = [y_lir, z_lir, y_rir, z_rir].
    pub fn to_array(&self) -> [f64; 4] {
        [self.y_left, self.z_left, self.y_right, self.z_right]
    }

    /// Lateral and vertical displacement of one side's rail.
    pub fn side(&self, side: Side) -> (f64, f64) {
        match side {
            Side::Left => (self.y_left, self.z_left),
            Side::Right => (self.y_right, self.z_right),
        }
    }

    /// Extra rotation δ = (z_lir − z_rir)/(2 L_r) of both rail profile frames (Eq. 11).
    pub fn delta(&self, l_r: f64) -> f64 {
        (self.z_left - self.z_right) / (2.0 * l_r)
    }

    /// al, vp, gv, cl.
    pub fn combinations(&self) -> (f64, f64, f64, f64) {
        (
            0.5 * (self.y_left + self.y_right),
            0.5 * (self.z_left + self.z_right),
            self.y_left - self.y_right,
            self.z_left - self.z_right,
        )
    }
}

/// The rail displacements at a moving wheelset and their first two time derivatives: what a
/// contact model needs of the track besides the wheelset's own lateral motion.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct RailMotion {
    /// q_r = [y_lir, z_lir, y_rir, z_rir], m.
    pub q: [f64; 4],
    pub q_dot: [f64; 4],
    pub q_ddot: [f64; 4],
}
