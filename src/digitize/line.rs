//! Line mode: a curve drawn as a line gives one point per pixel column, at the centroid row of
//! the matching pixels, or one point per separate vertical run of them.

use super::mask::Mask;

/// Pixel-space points (column, row) of the curve in `mask`, column by column.
///
/// Each run of vertically adjacent matching pixels is a candidate at its middle row. Without
/// `multi`, a column gives one point: its only run, or, where other ink of the colour shares the
/// column (a legend sample, a label, a second branch), the run nearest the previous column's
/// point (the longest run for the first column), so that separate runs are never averaged
/// into a point between them. With `multi`, every run gives its own point, so a multivalued
/// stretch (e.g. both branches at a jump) keeps every branch.
pub(crate) fn column_points(mask: &Mask, multi: bool) -> Vec<(f64, f64)> {
    let (x0, y0) = (f64::from(mask.region.x.0), f64::from(mask.region.y.0));
    let mut out = Vec::new();
    let mut previous: Option<f64> = None;
    for c in 0..mask.width() {
        let x = x0 + c as f64;
        // (middle row, length) of each run in this column.
        let mut runs: Vec<(f64, usize)> = Vec::new();
        let mut run: Option<(usize, usize)> = None; // (first row, length)
        for r in 0..=mask.height() {
            if r < mask.height() && mask.at(c, r) {
                run = Some(run.map_or((r, 1), |(s, n)| (s, n + 1)));
            } else if let Some((s, n)) = run.take() {
                runs.push((y0 + s as f64 + (n - 1) as f64 / 2.0, n));
            }
        }
        if multi {
            out.extend(runs.iter().map(|&(y, _)| (x, y)));
            continue;
        }
        let chosen = match previous {
            Some(p) => runs
                .iter()
                .min_by(|a, b| (a.0 - p).abs().total_cmp(&(b.0 - p).abs())),
            None => runs.iter().max_by_key(|r| r.1),
        };
        if let Some(&(y, _)) = chosen {
            out.push((x, y));
            previous = Some(y);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::super::mask::Region;
    use super::*;

    fn mask(rows: &[&str], x0: u32, y0: u32) -> Mask {
        let (w, h) = (rows[0].len() as u32, rows.len() as u32);
        Mask {
            region: Region {
                x: (x0, x0 + w),
                y: (y0, y0 + h),
            },
            on: rows
                .iter()
                .flat_map(|r| r.bytes().map(|b| b == b'#'))
                .collect(),
        }
    }

    #[test]
    fn centroid_per_column_and_runs() {
        let m = mask(&["#..", "#.#", "..#", "#.#"], 10, 20);
        // Column 10 holds two runs (rows 0-1 and 3): the longer one, not their average.
        assert_eq!(column_points(&m, false), [(10.0, 20.5), (12.0, 22.0)]);
        // Later columns follow the run nearest the previous point.
        let jumps = mask(&["#.#.", "..#.", "#..#", "#..#"], 0, 0);
        assert_eq!(
            column_points(&jumps, false),
            [(0.0, 2.5), (2.0, 0.5), (3.0, 2.5)]
        );
        assert_eq!(
            column_points(&m, true),
            [(10.0, 20.5), (10.0, 23.0), (12.0, 22.0)]
        );
    }
}
