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
//! The library never chooses the directory: the command line passes it (`kecsim` uses
//! `$KECSIM_CACHE_DIR`, else `$XDG_CACHE_HOME/kecsim`, else `~/.cache/kecsim`; `--no-cache`
//! turns it off).

use std::io::Write;
use std::path::{Path, PathBuf};

use super::geometry::{ContactGeometry, ContactSettings};
use super::lookup::{
    flange_angle, Jump, LookupTable1, LookupTable2, TableError, TableRow, TableSettings,
    FLANGE_FLANK_TOLERANCE_RAD, FLANGE_SCAN_STEP_M,
};

/// Bumped whenever the file layout or what a table holds changes (2: the trailing checksum).
const FORMAT_VERSION: u64 = 2;
/// Largest cache file read: a 1-entry table is ~0.5 MB, a 2-entry one a few tens of them.
pub const MAX_CACHE_FILE_BYTES: u64 = 256 << 20;
/// The first word of every table file.
const MAGIC: u64 = 0x6b65_6373_696d_7462; // "kecsimtb"
/// The first word of a flange-angle file.
const MAGIC_FLANGE: u64 = 0x6b65_6373_696d_6661; // "kecsimfa"
/// f64 words per row: y, gv, x (6), dx_dy (6), dx_dgv (6), contact angles (2), rolling radii (2),
/// curvatures (4), positions (4), two-point gaps (2).
const ROW_WORDS: usize = 34;

/// A directory of cached tables.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TableCache {
    dir: PathBuf,
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
        TableCache { dir: dir.into() }
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
        if let Some(mut t) = read(&path).filter(|t| t.len() == 1) {
            return Ok((t.remove(0), true));
        }
        let t = LookupTable1::build(geom, settings)?;
        write(&path, std::slice::from_ref(&t));
        Ok((t, false))
    }

    /// The flange angle of `geom` ([`flange_angle`]: the safety figures' Nadal limit), from the
    /// cache or computed and stored. Its 0.1 mm scans up both flanges were most of a cached run's
    /// preprocessing (~0.05 of 0.06 s on the MS scene). The key is the tables' (pair, contact
    /// settings, version) with the default table settings, and the scan's step and tolerance.
    /// The flag says whether it came from the cache.
    pub fn flange_angle(&self, geom: &ContactGeometry) -> Result<(f64, bool), TableError> {
        let path = self.flange_path(geom);
        if let Some(angle) = read_words(&path).and_then(|w| match w[..] {
            [MAGIC_FLANGE, FORMAT_VERSION, a] => Some(f64::from_bits(a)).filter(|a| a.is_finite()),
            _ => None,
        }) {
            return Ok((angle, true));
        }
        let angle = flange_angle(geom)?;
        write_words(&path, &[MAGIC_FLANGE, FORMAT_VERSION, angle.to_bits()]);
        Ok((angle, false))
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
        if let Some(columns) = read(&path).filter(|c| c.len() == gvs.len()) {
            return Ok((LookupTable2 { columns }, true));
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

/// The tables of words `w`, None if they do not parse.
fn decode(w: &[u64]) -> Option<Vec<LookupTable1>> {
    let mut it = w.iter().copied();
    let mut next = || it.next();
    if next()? != MAGIC || next()? != FORMAT_VERSION {
        return None;
    }
    let n = next()? as usize;
    let mut tables = Vec::with_capacity(n.min(1000));
    let fl = |x: u64| f64::from_bits(x);
    for _ in 0..n {
        let head: Vec<f64> = (0..6).map(|_| next().map(fl)).collect::<Option<_>>()?;
        let rows = next()? as usize;
        if rows < 2 || rows > w.len() {
            return None;
        }
        let mut rs = Vec::with_capacity(rows);
        for _ in 0..rows {
            let v: Vec<f64> = (0..ROW_WORDS).map(|_| next().map(fl)).collect::<Option<_>>()?;
            rs.push(row_from(&v));
        }
        let jumps = next()? as usize;
        if jumps > w.len() {
            return None;
        }
        let mut js = Vec::with_capacity(jumps);
        for _ in 0..jumps {
            let v: Vec<f64> = (0..4).map(|_| next().map(fl)).collect::<Option<_>>()?;
            js.push(Jump {
                y: v[0],
                left: v[1] != 0.0,
                s_wheel_before: v[2],
                s_wheel_after: v[3],
            });
        }
        let mut t = LookupTable1::from_rows(head[0], rs, js, head[1], head[2], head[3]);
        t.flange_limits = (head[4], head[5]);
        tables.push(t);
    }
    next().is_none().then_some(tables)
}

/// The tables in `path`, None when there is no readable, whole file.
fn read(path: &Path) -> Option<Vec<LookupTable1>> {
    decode(&read_words(path)?)
}

/// FNV-1a over the words `w`: the checksum a cache file ends with.
fn checksum(w: &[u64]) -> u64 {
    let mut k = Key::new();
    w.iter().for_each(|&x| k.word(x));
    k.0
}

/// The little-endian words of `path` without its checksum, None when it is not a regular file
/// (not followed through a link), is larger than [`MAX_CACHE_FILE_BYTES`], is not whole words or
/// fails its checksum.
fn read_words(path: &Path) -> Option<Vec<u64>> {
    let bytes = crate::files::read_bounded(path, MAX_CACHE_FILE_BYTES, true).ok()?;
    if bytes.len() % 8 != 0 {
        return None;
    }
    let mut w: Vec<u64> = bytes
        .chunks_exact(8)
        .map(|c| u64::from_le_bytes(c.try_into().unwrap_or([0; 8])))
        .collect();
    let sum = w.pop()?;
    (checksum(&w) == sum).then_some(w)
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
}
