//! Helpers for small golden renders kept as text.

use crate::image::HitBuffer;

/// The hit mask of `hits` on a `cols`×`rows` character grid: `#` where the
/// pixel at the centre of the cell hit the surface, `.` where it did not; one
/// line per row, each ending with `\n`.
pub fn ascii_mask(hits: &HitBuffer, cols: u32, rows: u32) -> String {
    let mut s = String::with_capacity(((cols + 1) * rows) as usize);
    if hits.width == 0 || hits.height == 0 {
        return s;
    }
    for r in 0..rows {
        let y = (((r as f64 + 0.5) * hits.height as f64 / rows as f64) as u32).min(hits.height - 1);
        for c in 0..cols {
            let x =
                (((c as f64 + 0.5) * hits.width as f64 / cols as f64) as u32).min(hits.width - 1);
            s.push(if hits.get(x, y).is_some() { '#' } else { '.' });
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
