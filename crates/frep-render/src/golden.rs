//! Helpers for small golden renders kept as text.

use crate::image::HitBuffer;

/// The hit mask of `hits` on a `cols`×`rows` character grid, one line per
/// row, each ending with `\n`. Each cell covers a block of pixels. It is `#`
/// where more than half of them hit the surface, `.` otherwise. A cell
/// smaller than a pixel uses the pixel under its centre.
pub fn ascii_mask(hits: &HitBuffer, cols: u32, rows: u32) -> String {
    let mut s = String::with_capacity(((cols + 1) * rows) as usize);
    if hits.width == 0 || hits.height == 0 {
        return s;
    }
    let span = |i: u32, n: u32, size: u32| {
        let a = (i as u64 * size as u64 / n as u64) as u32;
        let b = ((i as u64 + 1) * size as u64 / n as u64) as u32;
        if b > a {
            (a, b)
        } else {
            let c = (((i as f64 + 0.5) * size as f64 / n as f64) as u32).min(size - 1);
            (c, c + 1)
        }
    };
    for r in 0..rows {
        let (y0, y1) = span(r, rows, hits.height);
        for c in 0..cols {
            let (x0, x1) = span(c, cols, hits.width);
            let mut inside = 0u64;
            for y in y0..y1 {
                for x in x0..x1 {
                    inside += hits.get(x, y).is_some() as u64;
                }
            }
            let total = (y1 - y0) as u64 * (x1 - x0) as u64;
            s.push(if 2 * inside > total { '#' } else { '.' });
        }
        s.push('\n');
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::{Aabb, Camera};
    use crate::synthetic::sphere_hits;

    #[test]
    fn sphere_mask() {
        let b = Aabb::new([-1.0; 3], [1.0; 3]);
        let cam = Camera::orbit(&b, 0.0, 0.0, None);
        // Ortho: the box's bounding sphere (radius √3) fills the view; a sphere
        // of radius √3/2 fills the middle half.
        let hits = sphere_hits(&cam, 64, 64, [0.0; 3], 3f64.sqrt() / 2.0, None);
        let mask = ascii_mask(&hits, 8, 8);
        assert_eq!(
            mask,
            "........\n\
             ........\n\
             ...##...\n\
             ..####..\n\
             ..####..\n\
             ...##...\n\
             ........\n\
             ........\n"
        );
    }
}

#[cfg(test)]
mod lattice_tests {
    use super::*;
    use crate::camera::{Aabb, Camera};
    use crate::synthetic::Spheres;
    use crate::tiles::cast_tiled;

    /// The 100-sphere lattice seen from straight above (orthographic): a 5×5
    /// pattern of discs, kept as text.
    #[test]
    fn lattice_from_above() {
        let b = Aabb::new([-1.0; 3], [1.0; 3]);
        let cam = Camera::orbit(&b, 0.0, 90.0, None);
        let hits = cast_tiled(&Spheres::lattice_m2(), &cam, 96, 96, 16);
        let mask = ascii_mask(&hits, 24, 24);
        assert_eq!(mask, GOLDEN);
    }

    const GOLDEN: &str = "\
        ........................\n\
        ........................\n\
        ........................\n\
        ........................\n\
        ........................\n\
        ........................\n\
        ......############......\n\
        ......############......\n\
        ......##.#.##.#.##......\n\
        ......############......\n\
        ......##.#.##.#.##......\n\
        ......############......\n\
        ......############......\n\
        ......##.#.##.#.##......\n\
        ......############......\n\
        ......##.#.##.#.##......\n\
        ......############......\n\
        ......############......\n\
        ........................\n\
        ........................\n\
        ........................\n\
        ........................\n\
        ........................\n\
        ........................\n\
    ";
}
