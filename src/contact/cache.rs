//! A cache of the contact preprocessing on disk: the lookup tables of a wheel–rail pair (the
//! 1-entry table behind KEC's equivalent profiles and the `lookup` model, the 2-entry table's
//! columns), as the paper builds its tables once, before any simulation.
//!
//! **Key.** A 64-bit FNV-1a hash of everything a table is a function of: a format version,
//! kecsim's version, the wheel's and the rail's knots (their splines are the profiles), the rail
//! inclination, the gauge and its measuring depth, the wheelset's back-to-back, taping line and
//! r0, the contact solver's settings, the table settings and what is tabulated (the gauge
//! variations). Nothing else enters a table, so a hit is the table the build would give.
//!
//! **Files.** One file per table, `<dir>/<kind>-<key as 16 hex digits>.bin`: a magic word, the
//! format version, then the table as little-endian f64 words — its gauge variation, r0, L_r, z_r,
//! flange limits, its rows (every field of [`TableRow`]) and its jumps — so that a cached table
//! is the built one bit for bit (tested), and last a checksum of every word before it (FNV-1a),
//! so that an edited or damaged file is rebuilt, never trusted. A file is written to a temporary
//! name (created exclusively, never through a link) and renamed into place (two runs writing the
//! same table leave one whole file); a file that is not a regular file (a FIFO, a link), is larger
//! than [`MAX_CACHE_FILE_BYTES`], does not parse or fails its checksum is rebuilt and replaced.
//! Reading one costs at most its bound: nothing in the cache can hang a run or exhaust memory.
//!
//! **Plausibility.** A checksum detects accidents, not edits: whoever recomputes it can change a
//! table. So a table read is also checked against the geometry it is looked up for before it is
//! used: its counts against the file's size before anything is allocated, its gauge variation,
//! r0, L_r and z_r the pair's own, every row's values finite (but the "no secondary point" gaps)
//! and in their physical range — contact angles within ±90°, rolling radii within half of r0,
//! profile coordinates within the profiles' extents, y rising across the flange limits. The
//! flange angle (the safety figures' Nadal limit) is not stored at all: its file holds where the
//! scan found each flange's largest angle, and the angle is computed there from the geometry and
//! checked to be a flange's largest ([`flange_angle_at`]). A file that fails any of this is
//! rebuilt, and [`TableCache::take_notes`] says which file and why (a run prints it as a
//! warning).
//!
//! The library never chooses the directory: the command line passes it (`kecsim` uses
//! `$KECSIM_CACHE_DIR`, else `$XDG_CACHE_HOME/kecsim`, else `~/.cache/kecsim`; `--no-cache`
//! turns it off).

use std::io::Write;
use std::path::{Path, PathBuf};

use std::sync::{Arc, Mutex};

use super::geometry::{ContactGeometry, ContactSettings};
use super::lookup::{
    flange_angle_at, flange_angle_found, Jump, LookupTable1, LookupTable2, TableError, TableRow,
    TableSettings, FLANGE_FLANK_TOLERANCE_RAD, FLANGE_SCAN_STEP_M,
};

/// Bumped whenever the file layout or what a table holds changes (2: the trailing checksum; 3:
/// the flange-angle file holds where the angles were found, not the angle).
const FORMAT_VERSION: u64 = 3;
/// Largest cache file read: a 1-entry table is ~0.5 MB, a 2-entry one a few tens of them.
pub const MAX_CACHE_FILE_BYTES: u64 = 256 << 20;
/// The first word of every table file.
const MAGIC: u64 = 0x6b65_6373_696d_7462; // "kecsimtb"
/// The first word of a flange-angle file.
const MAGIC_FLANGE: u64 = 0x6b65_6373_696d_6661; // "kecsimfa"
/// f64 words per row: y, gv, x (6), dx_dy (6), dx_dgv (6), contact angles (2), rolling radii (2),
/// curvatures (4), positions (4), two-point gaps (2).
const ROW_WORDS: usize = 34;

/// A directory of cached tables, and what reading it found wrong (shared by its clones).
#[derive(Debug, Clone)]
pub struct TableCache {
    dir: PathBuf,
    /// One line per file rebuilt because it was implausible ([`TableCache::take_notes`]).
    notes: Arc<Mutex<Vec<String>>>,
}

/// Two caches are the same directory (their notes aside).
impl PartialEq for TableCache {
    fn eq(&self, other: &Self) -> bool {
        self.dir == other.dir
    }
}

impl Eq for TableCache {}

/// Why a cache file was not used.
enum Miss {
    /// There is no file (an ordinary miss: nothing to say).
    Absent,
    /// There is one, and this is what is wrong with it.
    Bad(String),
}

/// FNV-1a over 64-bit words.
#[derive(Debug, Clone, Copy)]
struct Key(u64);

impl Key {
    fn new() -> Self {
        Key(0xcbf2_9ce4_8422_2325)
    }
    fn word(&mut self, w: u64) {
        for b in w.to_le_bytes() {
            self.0 ^= b as u64;
            self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
    fn f(&mut self, v: f64) {
        self.word(v.to_bits());
    }
    fn str(&mut self, s: &str) {
        self.word(s.len() as u64);
        for b in s.bytes() {
            self.word(b as u64);
        }
    }
}

/// The key of a table of `geom` with `settings` over the gauge variations `gvs` (`kind` names
/// what is built from them).
fn key(kind: &str, geom: &ContactGeometry, settings: &TableSettings, gvs: &[f64]) -> u64 {
    let mut k = Key::new();
    k.word(FORMAT_VERSION);
    k.str(env!("CARGO_PKG_VERSION"));
    k.str(kind);
    let pair = &geom.pair;
    for profile in [&pair.wheel, &pair.rail] {
        let (s, z) = profile.knots();
        k.word(s.len() as u64);
        s.iter().chain(z).for_each(|&v| k.f(v));
    }
    k.f(pair.inclination.angle_rad);
    let g = &pair.rail_placement.gauge;
    for v in [
        g.gauge_m,
        g.measuring_depth_m,
        pair.wheelset.back_to_back_m,
        pair.wheelset.rolling_circle_from_back_m,
        pair.wheelset.nominal_radius_m,
    ] {
        k.f(v);
    }
    let ContactSettings {
        sample_step_m,
        newton_tolerance,
        max_iterations,
        max_step_m,
        two_point_tolerance_m,
        penetration_tolerance_m,
    } = geom.settings;
    for v in [
        sample_step_m,
        newton_tolerance,
        max_step_m,
        two_point_tolerance_m,
        penetration_tolerance_m,
    ] {
        k.f(v);
    }
    k.word(max_iterations as u64);
    let TableSettings {
        step_m,
        y_max_m,
        jump_threshold_m,
        refine_tolerance,
        refine_tolerance_s_m,
        refine_tolerance_angle_rad,
        max_refinements,
    } = *settings;
    for v in [
        step_m,
        y_max_m.unwrap_or(f64::NAN),
        jump_threshold_m,
        refine_tolerance,
        refine_tolerance_s_m,
        refine_tolerance_angle_rad,
    ] {
        k.f(v);
    }
    k.word(max_refinements as u64);
    k.word(gvs.len() as u64);
    gvs.iter().for_each(|&v| k.f(v));
    k.0
}

impl TableCache {
    /// A cache in `dir` (created when the first table is written).
    pub fn new(dir: impl Into<PathBuf>) -> Self {
        TableCache {
            dir: dir.into(),
            notes: Arc::default(),
        }
    }

    /// The lines saying which cache files were rebuilt since the last call, and why (each
    /// `contact table cache: FILE rebuilt: WHY`), taken: the caller prints them once.
    pub fn take_notes(&self) -> Vec<String> {
        self.notes
            .lock()
            .map(|mut n| std::mem::take(&mut *n))
            .unwrap_or_default()
    }

    /// Notes that `path` is rebuilt because of `why` (a missing file is no news).
    fn rebuilt(&self, path: &Path, miss: Miss) {
        if let Miss::Bad(why) = miss {
            if let Ok(mut n) = self.notes.lock() {
                n.push(format!("contact table cache: {} rebuilt: {why}", path.display()));
            }
        }
    }

    /// The directory.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    fn path(&self, kind: &str, key: u64) -> PathBuf {
        self.dir.join(format!("{kind}-{key:016x}.bin"))
    }

    /// The 1-entry table of `geom` ([`LookupTable1::build`]), from the cache or built and
    /// stored. The flag says whether it came from the cache.
    pub fn table1(
        &self,
        geom: &ContactGeometry,
        settings: &TableSettings,
    ) -> Result<(LookupTable1, bool), TableError> {
        let path = self.path("table1", key("table1", geom, settings, &[0.0]));
        match read(&path, geom, &[0.0]) {
            Ok(mut t) => return Ok((t.remove(0), true)),
            Err(miss) => self.rebuilt(&path, miss),
        }
        let t = LookupTable1::build(geom, settings)?;
        write(&path, std::slice::from_ref(&t));
        Ok((t, false))
    }

    /// The flange angle of `geom` ([`super::lookup::flange_angle`]: the safety figures' Nadal
    /// limit), from the cache or computed and stored. The file holds where the scan found each
    /// side's largest angle; the angle is computed there and checked ([`flange_angle_at`]). Its 0.1 mm scans up both flanges were most of a cached run's
    /// preprocessing (~0.05 of 0.06 s on the MS scene). The key is the tables' (pair, contact
    /// settings, version) with the default table settings, and the scan's step and tolerance.
    /// The flag says whether it came from the cache.
    pub fn flange_angle(&self, geom: &ContactGeometry) -> Result<(f64, bool), TableError> {
        let path = self.flange_path(geom);
        let cached = read_words(&path).and_then(|w| match w[..] {
            [MAGIC_FLANGE, FORMAT_VERSION, l, r] => {
                flange_angle_at(geom, [f64::from_bits(l), f64::from_bits(r)]).map_err(Miss::Bad)
            }
            _ => Err(Miss::Bad(format!(
                "{} words, not a flange-angle file of format {FORMAT_VERSION}",
                w.len()
            ))),
        });
        match cached {
            Ok(angle) => return Ok((angle, true)),
            Err(miss) => self.rebuilt(&path, miss),
        }
        let found = flange_angle_found(geom)?;
        let [l, r] = found.at_m;
        write_words(&path, &[MAGIC_FLANGE, FORMAT_VERSION, l.to_bits(), r.to_bits()]);
        Ok((found.angle_rad, false))
    }

    fn flange_path(&self, geom: &ContactGeometry) -> PathBuf {
        let mut k = Key(key("flange-angle", geom, &TableSettings::default(), &[]));
        k.f(FLANGE_SCAN_STEP_M);
        k.f(FLANGE_FLANK_TOLERANCE_RAD);
        self.path("flange-angle", k.0)
    }

    /// The 2-entry table of `geom` over `gvs` ([`LookupTable2::build`]), from the cache or built
    /// and stored.
    pub fn table2(
        &self,
        geom: &ContactGeometry,
        gvs: &[f64],
        settings: &TableSettings,
    ) -> Result<(LookupTable2, bool), TableError> {
        let path = self.path("table2", key("table2", geom, settings, gvs));
        match read(&path, geom, gvs) {
            Ok(columns) => return Ok((LookupTable2 { columns }, true)),
            Err(miss) => self.rebuilt(&path, miss),
        }
        let t = LookupTable2::build(geom, gvs, settings)?;
        write(&path, &t.columns);
        Ok((t, false))
    }
}

/// The tables as words.
fn encode(tables: &[LookupTable1]) -> Vec<u64> {
    let mut w = vec![MAGIC, FORMAT_VERSION, tables.len() as u64];
    let f = |w: &mut Vec<u64>, v: f64| w.push(v.to_bits());
    for t in tables {
        for v in [t.gv, t.r0, t.l_r, t.z_r, t.flange_limits.0, t.flange_limits.1] {
            f(&mut w, v);
        }
        w.push(t.rows.len() as u64);
        for r in &t.rows {
            for v in row_words(r) {
                f(&mut w, v);
            }
        }
        w.push(t.jumps.len() as u64);
        for j in &t.jumps {
            for v in [
                j.y,
                if j.left { 1.0 } else { 0.0 },
                j.s_wheel_before,
                j.s_wheel_after,
            ] {
                f(&mut w, v);
            }
        }
    }
    w
}

fn row_words(r: &TableRow) -> [f64; ROW_WORDS] {
    let mut v = [0.0; ROW_WORDS];
    let mut k = 0;
    let mut put = |xs: &[f64]| {
        v[k..k + xs.len()].copy_from_slice(xs);
        k += xs.len();
    };
    put(&[r.y, r.gv]);
    put(&r.x);
    put(&r.dx_dy);
    put(&r.dx_dgv);
    put(&r.contact_angle);
    put(&r.rolling_radius);
    put(&r.curvature);
    put(&r.position);
    put(&r.two_point_gap);
    v
}

fn row_from(v: &[f64]) -> TableRow {
    let arr = |a: usize, b: usize| v[a..b].to_vec();
    let mut r = TableRow {
        y: v[0],
        gv: v[1],
        ..TableRow::default()
    };
    r.x.copy_from_slice(&arr(2, 8));
    r.dx_dy.copy_from_slice(&arr(8, 14));
    r.dx_dgv.copy_from_slice(&arr(14, 20));
    r.contact_angle.copy_from_slice(&arr(20, 22));
    r.rolling_radius.copy_from_slice(&arr(22, 24));
    r.curvature.copy_from_slice(&arr(24, 28));
    r.position.copy_from_slice(&arr(28, 32));
    r.two_point_gap.copy_from_slice(&arr(32, 34));
    r
}

/// Words of a table's head: gv, r0, L_r, z_r, the two flange limits, the row count.
const HEAD_WORDS: usize = 7;
/// The largest |y| of a table's rows and jumps, m (the flange scan stops at 50 mm).
const Y_SPAN_M: f64 = 0.06;
/// Words of a stored jump.
const JUMP_WORDS: usize = 4;

/// The tables of words `w`, or what is wrong with them. Every count is held against the words
/// left before anything is allocated (a forged header asking for billions of rows costs nothing).
fn decode(w: &[u64]) -> Result<Vec<LookupTable1>, String> {
    let at = std::cell::Cell::new(0usize);
    let next = |what: &str| -> Result<u64, String> {
        let pos = at.get();
        let v = w
            .get(pos)
            .copied()
            .ok_or_else(|| format!("truncated: no {what} at word {pos}"))?;
        at.set(pos + 1);
        Ok(v)
    };
    let words_left = || (w.len() - at.get().min(w.len())) as u64;
    if next("magic word")? != MAGIC {
        return Err("not a table file (its magic word)".into());
    }
    let version = next("format version")?;
    if version != FORMAT_VERSION {
        return Err(format!("format {version}, expected {FORMAT_VERSION}"));
    }
    let n = next("table count")?;
    // Each table takes at least its head, two rows and a jump count.
    let least = (HEAD_WORDS + 2 * ROW_WORDS + 1) as u64;
    if n == 0 || n > w.len() as u64 / least {
        return Err(format!(
            "its header says {n} tables, but its {} words hold at most {}",
            w.len(),
            w.len() as u64 / least
        ));
    }
    let mut tables = Vec::with_capacity(n as usize);
    let fl = f64::from_bits;
    for k in 0..n {
        let head: Vec<f64> = (0..6)
            .map(|_| next("table head").map(fl))
            .collect::<Result<_, _>>()?;
        let rows = next("row count")?;
        let left = words_left();
        if rows < 2 || rows > left / ROW_WORDS as u64 {
            return Err(format!(
                "table {k}: its header says {rows} rows, but the {left} words left hold at most {}",
                left / ROW_WORDS as u64
            ));
        }
        let mut rs = Vec::with_capacity(rows as usize);
        for _ in 0..rows {
            let v: Vec<f64> = (0..ROW_WORDS)
                .map(|_| next("row").map(fl))
                .collect::<Result<_, _>>()?;
            rs.push(row_from(&v));
        }
        let jumps = next("jump count")?;
        let left = words_left();
        if jumps > left / JUMP_WORDS as u64 {
            return Err(format!(
                "table {k}: its header says {jumps} jumps, but the {left} words left hold at most {}",
                left / JUMP_WORDS as u64
            ));
        }
        let mut js = Vec::with_capacity(jumps as usize);
        for _ in 0..jumps {
            let v: Vec<f64> = (0..JUMP_WORDS)
                .map(|_| next("jump").map(fl))
                .collect::<Result<_, _>>()?;
            js.push(Jump {
                y: v[0],
                left: v[1] != 0.0,
                s_wheel_before: v[2],
                s_wheel_after: v[3],
            });
        }
        // The rows' order is checked before the slopes are built from them.
        if let Some(i) = (1..rs.len()).find(|&i| {
            !matches!(
                rs[i].y.partial_cmp(&rs[i - 1].y),
                Some(std::cmp::Ordering::Greater | std::cmp::Ordering::Equal)
            )
        }) {
            return Err(format!(
                "table {k}: row {i}: y = {} m after {} m (the rows must rise in y)",
                rs[i].y,
                rs[i - 1].y
            ));
        }
        let mut t = LookupTable1::from_rows(head[0], rs, js, head[1], head[2], head[3]);
        t.flange_limits = (head[4], head[5]);
        tables.push(t);
    }
    if at.get() != w.len() {
        return Err(format!("{} words after the last table", w.len() - at.get()));
    }
    Ok(tables)
}

/// What is implausible in `t`, a table of `geom` at gauge variation `gv` read from a file (None
/// when nothing is): the values a build of that geometry gives exactly (gv, r0, L_r, z_r), every
/// value finite but the "no secondary point" gaps (NaN), and each in its physical range.
fn implausible(t: &LookupTable1, geom: &ContactGeometry, gv: f64) -> Option<String> {
    let pair = &geom.pair;
    let r0 = pair.wheelset.nominal_radius_m;
    for (name, got, want) in [
        ("gauge variation", t.gv, gv),
        ("r0", t.r0, r0),
        ("L_r", t.l_r, pair.rail_placement.lateral_m),
        ("z_r", t.z_r, pair.rail_placement.vertical_m),
    ] {
        if got.to_bits() != want.to_bits() {
            return Some(format!("its {name} is {got} m, the pair's {want} m"));
        }
    }
    let (lo, hi) = t.flange_limits;
    if !(lo.is_finite() && hi.is_finite() && lo < hi && lo.abs() <= 0.05 && hi.abs() <= 0.05) {
        return Some(format!(
            "its flange limits {lo} .. {hi} m: expected a range within ±50 mm"
        ));
    }
    let span = |p: &crate::profile::Profile| {
        let (s, _) = p.knots();
        (
            s.iter().copied().fold(f64::INFINITY, f64::min),
            s.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        )
    };
    let (wheel, rail) = (span(&pair.wheel), span(&pair.rail));
    // Profile coordinates: a margin of 1 mm past the knots (the solver may end on the last one).
    // (Either sign: a side's coordinate may be its mirror's.)
    let within = |v: f64, (a, b): (f64, f64)| [v, -v].iter().any(|&v| v >= a - 1e-3 && v <= b + 1e-3);
    let right_angle = std::f64::consts::FRAC_PI_2;
    for (i, r) in t.rows.iter().enumerate() {
        let bad = |what: String| Some(format!("row {i} (y = {} m): {what}", r.y));
        let finite =
            r.x.iter()
                .chain(&r.dx_dy)
                .chain(&r.dx_dgv)
                .chain(&r.contact_angle)
                .chain(&r.rolling_radius)
                .chain(&r.curvature)
                .chain(&r.position)
                .chain([&r.y, &r.gv])
                .all(|v| v.is_finite());
        if !finite || r.two_point_gap.iter().any(|g| g.is_infinite()) {
            return bad("a value is not finite (NaN or infinite)".into());
        }
        if r.gv.to_bits() != gv.to_bits() {
            return bad(format!("gauge variation {} m, the table's {gv} m", r.gv));
        }
        // (A 2-entry table's columns span the common grid, wider than a column's own limits.)
        if r.y.abs() > Y_SPAN_M {
            return bad(format!("beyond ±{Y_SPAN_M} m of the centred position"));
        }
        if let Some(a) = r.contact_angle.iter().find(|a| a.abs() >= right_angle) {
            return bad(format!(
                "contact angle {:.3}°: expected within ±90°",
                a.to_degrees()
            ));
        }
        if let Some(rr) = r
            .rolling_radius
            .iter()
            .find(|&&rr| !(rr > 0.5 * r0 && rr < 1.5 * r0))
        {
            return bad(format!(
                "rolling radius {rr} m: expected within half of r0 = {r0} m"
            ));
        }
        if !(r.x[0].abs() < 2.0 && r.x[1].abs() < 0.2) {
            return bad(format!(
                "wheelset height {} m, roll {} rad: expected within 2 m and 0.2 rad",
                r.x[0], r.x[1]
            ));
        }
        let coords = [
            (r.x[2], wheel, "left wheel"),
            (r.x[3], rail, "left rail"),
            (r.x[4], wheel, "right wheel"),
            (r.x[5], rail, "right rail"),
        ];
        if let Some((v, (a, b), name)) = coords.iter().find(|(v, range, _)| !within(*v, *range)) {
            return bad(format!(
                "{name} profile coordinate {v} m: outside the profile's {a} .. {b} m"
            ));
        }
        if let Some(p) = r.position.iter().find(|p| p.abs() > 2.0) {
            return bad(format!(
                "contact position {p} m: expected within 2 m of the wheelset's centre"
            ));
        }
    }
    for (j, jump) in t.jumps.iter().enumerate() {
        if jump.y.is_nan()
            || jump.y.abs() > Y_SPAN_M
            || !within(jump.s_wheel_before, wheel)
            || !within(jump.s_wheel_after, wheel)
        {
            return Some(format!(
                "jump {j} at y = {} m: beyond ±{Y_SPAN_M} m or off the wheel profile",
                jump.y
            ));
        }
    }
    None
}

/// The tables in `path` of `geom` at the gauge variations `gvs`: none when there is no file; a
/// reason when it is not a whole, checked file of plausible tables.
fn read(path: &Path, geom: &ContactGeometry, gvs: &[f64]) -> Result<Vec<LookupTable1>, Miss> {
    let tables = decode(&read_words(path)?).map_err(Miss::Bad)?;
    if tables.len() != gvs.len() {
        return Err(Miss::Bad(format!(
            "{} tables, expected {}",
            tables.len(),
            gvs.len()
        )));
    }
    for (k, (t, &gv)) in tables.iter().zip(gvs).enumerate() {
        if let Some(why) = implausible(t, geom, gv) {
            let which = if gvs.len() > 1 {
                format!("table {k}: ")
            } else {
                String::new()
            };
            return Err(Miss::Bad(format!("{which}{why}")));
        }
    }
    Ok(tables)
}

/// FNV-1a over the words `w`: the checksum a cache file ends with.
fn checksum(w: &[u64]) -> u64 {
    let mut k = Key::new();
    w.iter().for_each(|&x| k.word(x));
    k.0
}

/// The little-endian words of `path` without its checksum: [`Miss::Absent`] when there is no
/// file, else what is wrong — not a regular file (not followed through a link), larger than
/// [`MAX_CACHE_FILE_BYTES`], not whole words, or its checksum fails.
fn read_words(path: &Path) -> Result<Vec<u64>, Miss> {
    let bytes = match crate::files::read_bounded(path, MAX_CACHE_FILE_BYTES, true) {
        Ok(b) => b,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Err(Miss::Absent),
        Err(e) => return Err(Miss::Bad(format!("cannot be read: {e}"))),
    };
    if bytes.len() % 8 != 0 || bytes.is_empty() {
        return Err(Miss::Bad(format!(
            "{} bytes: not whole 8-byte words",
            bytes.len()
        )));
    }
    let mut w: Vec<u64> = bytes
        .chunks_exact(8)
        .map(|c| u64::from_le_bytes(c.try_into().unwrap_or([0; 8])))
        .collect();
    let sum = w.pop().ok_or(Miss::Absent)?;
    if checksum(&w) != sum {
        return Err(Miss::Bad(
            "its checksum does not match: the file is damaged".into(),
        ));
    }
    Ok(w)
}

/// Stores the tables at `path` through a temporary file renamed into place; a cache that cannot
/// be written is only a missed speed-up (said on stderr by the caller's next miss), so errors
/// are dropped.
fn write(path: &Path, tables: &[LookupTable1]) {
    write_words(path, &encode(tables));
}

/// [`write`] of any words.
fn write_words(path: &Path, words: &[u64]) {
    let Some(dir) = path.parent() else { return };
    if std::fs::create_dir_all(dir).is_err() {
        return;
    }
    let tmp = dir.join(format!(
        ".{}.{}.tmp",
        path.file_name().and_then(|n| n.to_str()).unwrap_or("table"),
        std::process::id()
    ));
    let mut bytes: Vec<u8> = words.iter().flat_map(|w| w.to_le_bytes()).collect();
    bytes.extend_from_slice(&checksum(words).to_le_bytes());
    let ok = crate::files::create_side_file(&tmp)
        .and_then(|mut f| f.write_all(&bytes).and_then(|_| f.sync_all()))
        .is_ok();
    if ok && std::fs::rename(&tmp, path).is_ok() {
        return;
    }
    std::fs::remove_file(&tmp).ok();
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::lookup::flange_angle;
    use crate::profile::placement::WheelRailPair;
    use crate::profile::StandardProfile;

    /// Bit for bit (NaN, the rows' "no secondary point", included).
    fn bits(r: &TableRow) -> Vec<u64> {
        row_words(r).iter().map(|v| v.to_bits()).collect()
    }

    fn same(a: &LookupTable1, b: &LookupTable1) {
        assert_eq!(a.rows.len(), b.rows.len());
        for (p, q) in a.rows.iter().zip(&b.rows) {
            assert_eq!(bits(p), bits(q));
        }
        assert_eq!(a.jumps, b.jumps);
        assert_eq!(a.flange_limits, b.flange_limits);
        assert_eq!((a.gv, a.r0, a.l_r, a.z_r), (b.gv, b.r0, b.l_r, b.z_r));
        // Every look-up the same, bit for bit (the PCHIP slopes rebuilt from the rows).
        let (lo, hi) = a.range();
        for k in 0..=400 {
            let y = (lo + (hi - lo) * k as f64 / 400.0).clamp(lo, hi);
            assert_eq!(
                bits(&a.lookup(y).unwrap()),
                bits(&b.lookup(y).unwrap()),
                "y = {y}"
            );
        }
    }

    /// A cached table is the built one bit for bit; a second geometry (another gauge) is another
    /// key; a damaged file is rebuilt and replaced.
    /// The flange angle from the cache is the computed one, bit for bit; another pair has
    /// another key; a damaged or foreign file is computed again and replaced, never trusted.
    #[test]
    fn a_cached_flange_angle_is_the_computed_one() {
        let dir = std::env::temp_dir().join(format!("kecsim-cache-flange-{}", std::process::id()));
        std::fs::remove_dir_all(&dir).ok();
        let cache = TableCache::new(&dir);
        let pair =
            WheelRailPair::standard(StandardProfile::S1002, StandardProfile::Rail60E1, "1:40").unwrap();
        let geom = ContactGeometry::with_defaults(pair.clone());
        let computed = flange_angle(&geom).unwrap();
        let (first, hit) = cache.flange_angle(&geom).unwrap();
        assert!(!hit);
        assert_eq!(first.to_bits(), computed.to_bits());
        let (cached, hit) = cache.flange_angle(&geom).unwrap();
        assert!(hit);
        assert_eq!(cached.to_bits(), computed.to_bits());
        // S1002's flange: about 70°.
        assert!(
            (computed.to_degrees() - 70.0).abs() < 1.5,
            "{}",
            computed.to_degrees()
        );
        // Another inclination: another file, another angle.
        let other = ContactGeometry::with_defaults(
            WheelRailPair::standard(StandardProfile::S1002, StandardProfile::Rail60E1, "1:20").unwrap(),
        );
        let (a20, hit) = cache.flange_angle(&other).unwrap();
        assert!(!hit);
        assert_eq!(a20.to_bits(), flange_angle(&other).unwrap().to_bits());
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 2);
        // A damaged file (a word short) and a foreign one (a table's magic word): computed again.
        for g in [&geom, &other] {
            let file = cache.flange_path(g);
            let bytes = std::fs::read(&file).unwrap();
            let mut foreign = bytes.clone();
            foreign[..8].copy_from_slice(&MAGIC.to_le_bytes());
            for damaged in [bytes[..16].to_vec(), foreign] {
                std::fs::write(&file, &damaged).unwrap();
                let (again, hit) = cache.flange_angle(g).unwrap();
                assert!(!hit, "a damaged file is not read");
                assert_eq!(again.to_bits(), flange_angle(g).unwrap().to_bits());
                assert_eq!(std::fs::read(&file).unwrap(), bytes, "replaced by the whole file");
            }
        }
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn a_cached_table_is_the_built_table() {
        let dir = std::env::temp_dir().join(format!("kecsim-cache-test-{}", std::process::id()));
        std::fs::remove_dir_all(&dir).ok();
        let cache = TableCache::new(&dir);
        let pair =
            WheelRailPair::standard(StandardProfile::S1002, StandardProfile::Rail60E1, "1:40").unwrap();
        let geom = ContactGeometry::with_defaults(pair.clone());
        let settings = TableSettings::default();
        let (built, hit) = cache.table1(&geom, &settings).unwrap();
        assert!(!hit);
        assert!(
            !built.jumps.is_empty(),
            "S1002/60E1 jumps: the jumps must survive the cache"
        );
        let (cached, hit) = cache.table1(&geom, &settings).unwrap();
        assert!(hit);
        same(&built, &cached);
        same(&built, &LookupTable1::build(&geom, &settings).unwrap());
        // Another gauge: another table.
        let mut wider = pair.clone();
        wider.rail_placement.gauge.gauge_m += 0.002;
        let geom2 = ContactGeometry::with_defaults(wider);
        assert_ne!(
            key("table1", &geom, &settings, &[0.0]),
            key("table1", &geom2, &settings, &[0.0])
        );
        // A damaged file: rebuilt.
        let file = std::fs::read_dir(&dir).unwrap().next().unwrap().unwrap().path();
        let bytes = std::fs::read(&file).unwrap();
        std::fs::write(&file, &bytes[..bytes.len() / 2]).unwrap();
        let (again, hit) = cache.table1(&geom, &settings).unwrap();
        assert!(!hit);
        same(&built, &again);
        assert_eq!(std::fs::read(&file).unwrap(), bytes, "replaced by the whole file");
        // The 2-entry table too.
        let gvs = [-2e-3, -1e-3, 0.0, 1e-3, 2e-3];
        let (t2, hit) = cache.table2(&geom, &gvs, &settings).unwrap();
        assert!(!hit);
        let (c2, hit) = cache.table2(&geom, &gvs, &settings).unwrap();
        assert!(hit);
        for (a, b) in t2.columns.iter().zip(&c2.columns) {
            same(a, b);
        }
        std::fs::remove_dir_all(&dir).ok();
    }

    /// Rewrites `file` as `edit` changes its words, with the checksum recomputed (an edit, not
    /// an accident).
    fn forge(file: &Path, edit: impl Fn(&mut Vec<u64>)) {
        let bytes = std::fs::read(file).unwrap();
        let mut w: Vec<u64> = bytes
            .chunks_exact(8)
            .map(|c| u64::from_le_bytes(c.try_into().unwrap()))
            .collect();
        w.pop();
        edit(&mut w);
        write_words(file, &w);
    }

    /// Issue 66, class 9: a forged file with a valid checksum is checked for plausibility — a
    /// header asking for billions of rows (no allocation), NaN rows, a contact angle past 90°,
    /// a flange angle moved off the flange — rebuilt, and the note names the file and why.
    #[test]
    fn forged_cache_files_are_rebuilt_and_named() {
        let dir = std::env::temp_dir().join(format!("kecsim-cache-forged-{}", std::process::id()));
        std::fs::remove_dir_all(&dir).ok();
        let cache = TableCache::new(&dir);
        let pair =
            WheelRailPair::standard(StandardProfile::S1002, StandardProfile::Rail60E1, "1:40").unwrap();
        let geom = ContactGeometry::with_defaults(pair);
        let settings = TableSettings::default();
        let (built, _) = cache.table1(&geom, &settings).unwrap();
        assert!(cache.take_notes().is_empty(), "a first build is no news");
        let file = cache.path("table1", key("table1", &geom, &settings, &[0.0]));
        let whole = std::fs::read(&file).unwrap();
        // Word 9 is table 0's row count (magic, version, count, six head words).
        let row0 = 10;
        type Edit = Box<dyn Fn(&mut Vec<u64>)>;
        let cases: Vec<(&str, Edit)> = vec![
            ("rows, but the", Box::new(|w: &mut Vec<u64>| w[9] = 1 << 40)),
            (
                "tables, but its",
                Box::new(|w: &mut Vec<u64>| w[2] = u64::MAX / 2),
            ),
            (
                "not finite",
                Box::new(move |w: &mut Vec<u64>| {
                    for k in 2..ROW_WORDS {
                        w[row0 + 5 * ROW_WORDS + k] = f64::NAN.to_bits();
                    }
                }),
            ),
            (
                "contact angle 100.000°",
                Box::new(move |w: &mut Vec<u64>| {
                    w[row0 + 7 * ROW_WORDS + 20] = 100f64.to_radians().to_bits();
                }),
            ),
            (
                "rolling radius",
                Box::new(move |w: &mut Vec<u64>| w[row0 + 3 * ROW_WORDS + 22] = (-0.46f64).to_bits()),
            ),
            ("r0 is", Box::new(|w: &mut Vec<u64>| w[4] = 0.5f64.to_bits())),
        ];
        for (want, edit) in cases {
            forge(&file, edit);
            let (again, hit) = cache.table1(&geom, &settings).unwrap();
            assert!(!hit, "{want}: a forged file is not used");
            assert_eq!(again.rows.len(), built.rows.len());
            let notes = cache.take_notes();
            assert_eq!(notes.len(), 1, "{notes:?}");
            assert!(
                notes[0].contains(&file.display().to_string())
                    && notes[0].contains("rebuilt")
                    && notes[0].contains(want),
                "{want}: {notes:?}"
            );
            assert_eq!(std::fs::read(&file).unwrap(), whole, "replaced by the whole file");
        }
        // The flange angle (the Nadal limit): the file holds where the angles were found; a
        // place moved off the flange's largest angle is found out and the angle computed again.
        let (angle, _) = cache.flange_angle(&geom).unwrap();
        let ffile = cache.flange_path(&geom);
        for (want, at) in [
            ("not a flange contact", 0.0f64),
            ("left wheel's contact angle", f64::NAN),
        ] {
            forge(&ffile, |w| {
                let y = f64::from_bits(w[2]);
                w[2] = if at.is_nan() {
                    (y - 1.5e-3).to_bits()
                } else {
                    at.to_bits()
                };
            });
            let (again, hit) = cache.flange_angle(&geom).unwrap();
            assert!(!hit, "{want}");
            assert_eq!(again.to_bits(), angle.to_bits());
            let notes = cache.take_notes();
            assert!(
                notes.len() == 1
                    && notes[0].contains(&ffile.display().to_string())
                    && notes[0].contains(want),
                "{want}: {notes:?}"
            );
        }
        let (cached, hit) = cache.flange_angle(&geom).unwrap();
        assert!(hit && cached.to_bits() == angle.to_bits());
        std::fs::remove_dir_all(&dir).ok();
    }
}
