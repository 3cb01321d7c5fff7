//! Line mode: a curve drawn as a line gives one point per pixel column, at the centroid row of
//! the matching pixels, or one point per separate vertical run of them.

use super::mask::Mask;

/// Pixel-space points (column, row) of the curve in `mask`, column by column.
///
/// Without `multi`, each column with matching pixels gives one point at the mean row of all of
/// them. With `multi`, each run of vertically adjacent matching pixels gives its own point at the
/// run's middle, so a multivalued stretch (e.g. both branches at a jump) keeps every branch.
pub(crate) fn column_points(mask: &Mask, multi: bool) -> Vec<(f64, f64)> {
    let (x0, y0) = (f64::from(mask.region.x.0), f64::from(mask.region.y.0));
    let mut out = Vec::new();
    for c in 0..mask.width() {
        let x = x0 + c as f64;
        let (mut sum, mut count) = (0usize, 0usize);
        let mut run: Option<(usize, usize)> = None; // (first row, length)
        for r in 0..mask.height() {
            if mask.at(c, r) {
                sum += r;
                count += 1;
                run = Some(run.map_or((r, 1), |(s, n)| (s, n + 1)));
            } else if let Some((s, n)) = run.take() {
                if multi {
                    out.push((x, y0 + s as f64 + (n - 1) as f64 / 2.0));
                }
            }
        }
        if let (true, Some((s, n))) = (multi, run) {
            out.push((x, y0 + s as f64 + (n - 1) as f64 / 2.0));
        }
        if !multi && count > 0 {
            out.push((x, y0 + sum as f64 / count as f64));
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
        assert_eq!(
            column_points(&m, false),
            [(10.0, 20.0 + 4.0 / 3.0), (12.0, 22.0)]
        );
        assert_eq!(
            column_points(&m, true),
            [(10.0, 20.5), (10.0, 23.0), (12.0, 22.0)]
        );
    }
}
