//! Order checks of curve points: within one curve, speeds increase strictly down a file and no
//! speed appears twice (in any file of the data set); and the grouping of Munro points into
//! curves by load, with the one notion of "same load" that [`super::same_load`] defines.

use super::csv_curves::Row;
use super::same_load::same_load;
use crate::error::Result;
use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};

/// Assigns loads to curves as [`super::MunroData::loads`] and [`super::MunroData::curve`] group
/// them: a load joins the curve whose first-seen load it is [`same_load`] with, or starts a new
/// curve. Loads that would make that grouping ambiguous (one load the same as two curves' loads,
/// or a new curve's load the same as a point already in another curve) are refused, so that
/// every point belongs to exactly one `curve(l)` for `l` in `loads()`.
///
/// Loads must be positive and finite: then the bit patterns of the numbers order as the numbers,
/// which the range queries below rely on.
#[derive(Default)]
pub(crate) struct LoadGroups {
    /// Curve id of each distinct load value seen (keyed by its bits).
    values: BTreeMap<u64, usize>,
    /// Curve id of each curve's first-seen load (keyed by its bits).
    firsts: BTreeMap<u64, usize>,
    /// First-seen load of each curve, by id.
    first_of: Vec<f64>,
}

/// Keys of every load `same_load` with `load` lie in this range (a little wider than needed:
/// |a - b| <= 1e-9 max(a, b) bounds b within a (1 -+ 1e-9)^(-+1)).
fn near(load: f64) -> std::ops::RangeInclusive<u64> {
    let (a, b) = (
        (load * (1.0 - 2e-9)).to_bits(),
        (load * (1.0 + 2e-9)).to_bits(),
    );
    // Ordered either way, so that no input can make `BTreeMap::range` panic on a reversed range.
    a.min(b)..=a.max(b)
}

impl LoadGroups {
    /// The curve id of positive finite `load_n`, or the reason the load is ambiguous.
    pub(crate) fn curve_of(&mut self, load_n: f64) -> std::result::Result<usize, String> {
        if let Some(&id) = self.values.get(&load_n.to_bits()) {
            return Ok(id);
        }
        // At most a few curves' first loads lie this close to each other (they are pairwise not
        // the same load), so this scan is short.
        let mut matches = self
            .firsts
            .range(near(load_n))
            .map(|(_, &id)| id)
            .filter(|&id| same_load(self.first_of[id], load_n));
        let id = match (matches.next(), matches.next()) {
            (Some(a), Some(b)) => {
                return Err(format!(
                    "load {load_n} N is the same (relative 1e-9) as the loads of two curves, \
                     {} N and {} N: give each curve's points one load value",
                    self.first_of[a], self.first_of[b]
                ))
            }
            (Some(id), None) => id,
            (None, _) => {
                // A new curve: no point of another curve may be the same load as its load, or
                // that point would belong to two curves.
                if let Some((&bits, &other)) = self
                    .values
                    .range(near(load_n))
                    .find(|(&bits, _)| same_load(f64::from_bits(bits), load_n))
                {
                    return Err(format!(
                        "load {load_n} N is the same (relative 1e-9) as the load {} N of a point \
                         of the curve at {} N but not as that curve's load: give each curve's \
                         points one load value",
                        f64::from_bits(bits),
                        self.first_of[other]
                    ));
                }
                let id = self.first_of.len();
                self.first_of.push(load_n);
                self.firsts.insert(load_n.to_bits(), id);
                id
            }
        };
        self.values.insert(load_n.to_bits(), id);
        Ok(id)
    }
}

/// Where a point was seen.
#[derive(Clone, Copy)]
struct Seen {
    /// Index into [`CurveOrder::files`].
    file: usize,
    line: usize,
    /// The load of that point (Munro), to show when it differs from the duplicate's.
    load_n: Option<f64>,
}

/// Tracks the points seen so far, curve by curve (a curve is identified by a small number: the
/// id from [`LoadGroups`], or 0 for a data set with a single curve).
///
/// Within a file the checks keep each curve's speeds increasing, so a repeated speed of the
/// same file is found by comparing with the curve's last point (or, when the new speed is lower,
/// by a binary search); only points of files that more files follow go into a hash map, for the
/// duplicates across files. A single large file is thus checked without hashing every point.
#[derive(Default)]
pub(crate) struct CurveOrder {
    /// Files started so far, in order.
    files: Vec<PathBuf>,
    /// Speeds (increasing) and points of each curve in the current file, indexed by curve.
    current: Vec<Vec<(f64, Seen)>>,
    /// The curves with points in the current file (so that starting a file costs the points
    /// of the last one, not the number of curves).
    touched: Vec<usize>,
    /// Whether the current file's points must be remembered for the files that follow.
    keep: bool,
    /// Where each (curve, speed bits) pair was first seen in the earlier files.
    earlier: HashMap<(usize, u64), Seen>,
    /// Points of each curve so far, over every file.
    counts: Vec<usize>,
}

/// Speeds one curve may have: a pp DTE or dynamic-factor point is a steady state, measured at
/// tens to hundreds of speeds (Munro's grid has 81). Beyond this a file is a time series or a
/// sweep sampled far finer than any steady state, and every fit and prediction would take
/// minutes for nothing.
pub(crate) const MAX_CURVE_POINTS: usize = 10_000;

impl CurveOrder {
    /// Start checking the rows of `file` (speeds are sorted within each file); `more_follow`
    /// tells whether other files of the data set are checked after it.
    pub(crate) fn start_file(&mut self, file: &Path, more_follow: bool) {
        for curve in self.touched.drain(..) {
            let Some(points) = self.current.get_mut(curve) else {
                continue;
            };
            if self.keep {
                for (speed, seen) in points.iter() {
                    self.earlier
                        .entry((curve, speed.to_bits()))
                        .or_insert(*seen);
                }
            }
            points.clear();
        }
        self.files.push(file.to_path_buf());
        self.keep = more_follow;
    }

    /// Check the point of `row` at `speed_rpm` on curve `curve` (at `load_n` for Munro data) of
    /// the current file; the error names the offending row and its speed column `field`.
    pub(crate) fn check(
        &mut self,
        curve: usize,
        load_n: Option<f64>,
        speed_rpm: f64,
        row: &Row,
        field: &str,
    ) -> Result<()> {
        let file = self.files.len().saturating_sub(1);
        let duplicate = |s: &Seen, files: &[PathBuf]| {
            let mut at = if s.file == file {
                format!("line {}", s.line)
            } else {
                let f = files.get(s.file).map(|f| f.display().to_string());
                format!("{}:{}", f.unwrap_or_default(), s.line)
            };
            if let (Some(here), Some(there)) = (load_n, s.load_n) {
                if here != there {
                    at = format!("{at}, load {there} N: loads within relative 1e-9 are one curve");
                }
            }
            row.error(
                field,
                format!(
                    "duplicate speed {speed_rpm} rpm{} (also at {at})",
                    label(load_n)
                ),
            )
        };
        if !self.earlier.is_empty() {
            if let Some(s) = self.earlier.get(&(curve, speed_rpm.to_bits())) {
                return Err(duplicate(s, &self.files));
            }
        }
        if self.counts.len() <= curve {
            self.counts.resize(curve + 1, 0);
        }
        self.counts[curve] += 1;
        if self.counts[curve] > MAX_CURVE_POINTS {
            return Err(row.error(
                field,
                format!(
                    "more than {MAX_CURVE_POINTS} speeds{}: each point is a steady state, \
                     measured at tens to hundreds of speeds; thin the data (e.g. keep every \
                     10th row) or average it onto a coarser grid",
                    label(load_n)
                ),
            ));
        }
        if self.current.len() <= curve {
            self.current.resize_with(curve + 1, Vec::new);
        }
        let points = &mut self.current[curve];
        if let Some(&(prev, ref seen)) = points.last() {
            if speed_rpm == prev {
                return Err(duplicate(seen, &self.files));
            }
            if speed_rpm < prev {
                if let Ok(i) = points.binary_search_by(|(s, _)| s.total_cmp(&speed_rpm)) {
                    return Err(duplicate(&points[i].1, &self.files));
                }
                return Err(row.error(
                    field,
                    format!(
                        "speeds not sorted{}: {speed_rpm} rpm follows {prev} rpm; list each \
                         curve by increasing speed",
                        label(load_n)
                    ),
                ));
            }
        }
        if points.is_empty() {
            self.touched.push(curve);
        }
        points.push((
            speed_rpm,
            Seen {
                file,
                line: row.line,
                load_n,
            },
        ));
        Ok(())
    }
}

/// " in the curve at load L N" for Munro points, "" for the single Kubo curve.
fn label(load_n: Option<f64>) -> String {
    load_n.map_or(String::new(), |l| format!(" in the curve at load {l} N"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn near_loads_are_one_curve_and_ambiguous_ones_refused() {
        let mut g = LoadGroups::default();
        assert_eq!(g.curve_of(3780.0), Ok(0));
        assert_eq!(g.curve_of(3780.0 + 1e-7), Ok(0));
        assert_eq!(g.curve_of(2835.0), Ok(1));
        assert_eq!(g.curve_of(3780.0), Ok(0));
        // 0.6e-9 above the first load joins it; 1.2e-9 above is not the same as 3780 but is
        // the same as the point at 0.6e-9, which would then sit in two curves.
        let a = 1000.0;
        let mut g = LoadGroups::default();
        assert_eq!(g.curve_of(a), Ok(0));
        assert_eq!(g.curve_of(a * (1.0 + 0.6e-9)), Ok(0));
        assert!(g.curve_of(a * (1.0 + 1.2e-9)).is_err());
        // Two curves 1.5e-9 apart, then a load between them that is the same as both.
        let mut g = LoadGroups::default();
        assert_eq!(g.curve_of(a), Ok(0));
        assert_eq!(g.curve_of(a * (1.0 + 1.5e-9)), Ok(1));
        let e = g.curve_of(a * (1.0 + 0.75e-9)).unwrap_err();
        assert!(e.contains("two curves"), "{e}");
    }
}
