//! The one notion of "same load" of the data layer (relative tolerance 1e-9).

/// Whether two loads are the same (relative tolerance 1e-9). `MunroData::loads` and
/// `MunroData::curve` group points with it, `load_munro` checks speeds for duplicates within the
/// curves it forms (refusing loads that would make the grouping ambiguous), and rig.toml's
/// `[ste]` table takes two loads it calls the same for one load given twice.
pub fn same_load(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * a.abs().max(b.abs())
}
