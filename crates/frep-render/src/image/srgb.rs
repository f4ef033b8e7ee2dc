//! The sRGB transfer function and its byte encoding (by table).

/// sRGB component in `[0, 1]` to linear.
pub fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// Linear component to sRGB in `[0, 1]` (clamped).
pub fn linear_to_srgb(c: f32) -> f32 {
    let c = c.clamp(0.0, 1.0);
    if c <= 0.003_130_8 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

pub(super) fn to_byte(c: f32) -> u8 {
    (c.clamp(0.0, 1.0) * 255.0 + 0.5) as u8
}

/// Cells of [`srgb_byte`]'s index over `[0, 1]`.
const SRGB_CELLS: usize = 4096;

/// `to_byte(linear_to_srgb(c))` without a `powf`.
/// - The byte is the number of thresholds at or below `c`.
/// - Threshold `b - 1` is the smallest `c` whose byte is at least `b`. It
///   is found once, by bisection over the `f32`s. So the result is the same
///   byte, bit for bit, for every finite `c`.
/// - An index gives the count below `c`'s cell of `1/SRGB_CELLS`, centred
///   on a multiple of `1/SRGB_CELLS`. That is exact: the scaling is by a
///   power of two.
/// - A cell holds at most one threshold (checked when the table is built),
///   compared with `c`.
#[cfg_attr(not(test), allow(dead_code))]
fn srgb_byte(c: f32) -> u8 {
    srgb_table().byte(c)
}

/// The index of [`srgb_byte`] and each cell's next threshold.
#[derive(Debug)]
pub(super) struct SrgbTable {
    /// Per cell, the number of thresholds below it.
    idx: Box<[u8; SRGB_CELLS + 1]>,
    /// Per cell, the first threshold not below it (`t[idx[cell]]`; +∞
    /// past the last): read independently of `idx`, so the two loads
    /// overlap.
    next: Box<[f32; SRGB_CELLS + 1]>,
}

/// The smallest `c` in `[0, 1]` whose `to_byte(linear_to_srgb(c))` is at
/// least `want`, found by bisection over the `f32`s (non-negative ones are
/// ordered like their bit patterns).
fn srgb_threshold(want: u8) -> f32 {
    let byte = |bits: u32| to_byte(linear_to_srgb(f32::from_bits(bits)));
    let (mut lo, mut hi) = (0u32, 1.0f32.to_bits());
    while lo < hi {
        let mid = lo + (hi - lo) / 2;
        if byte(mid) >= want {
            hi = mid;
        } else {
            lo = mid + 1;
        }
    }
    f32::from_bits(lo)
}

pub(super) fn srgb_table() -> &'static SrgbTable {
    static T: std::sync::OnceLock<SrgbTable> = std::sync::OnceLock::new();
    T.get_or_init(|| {
        let t: [f32; 255] = std::array::from_fn(|i| srgb_threshold(i as u8 + 1));
        // Cell `q` is `[q − ½, q + ½] / SRGB_CELLS` (both ends: a value
        // halfway between two whole numbers rounds to the even one).
        let edge = |q: usize| (q as f64 - 0.5) / SRGB_CELLS as f64;
        let idx: Box<[u8; SRGB_CELLS + 1]> = Box::new(std::array::from_fn(|q| {
            t.partition_point(|&v| f64::from(v) < edge(q)) as u8
        }));
        // The steepest part of the curve climbs about 3300 bytes per unit,
        // fewer than the cells: no cell holds two thresholds.
        assert!(
            (0..=SRGB_CELLS).all(|q| {
                t.partition_point(|&v| f64::from(v) <= edge(q + 1)) - idx[q] as usize <= 1
            }),
            "sRGB index: two thresholds in one cell"
        );
        let next = Box::new(std::array::from_fn(|q| {
            t.get(idx[q] as usize).copied().unwrap_or(f32::INFINITY)
        }));
        SrgbTable { idx, next }
    })
}

impl SrgbTable {
    /// [`srgb_byte`], without a branch or a float-to-integer cast (so that
    /// loops over pixels vectorise): `c` is clamped to `[0, 1]` first,
    /// which changes no byte (every threshold is positive, and the last is
    /// at most 1); NaN becomes 0 (`max` takes the number), byte 0, as
    /// `to_byte` gives.
    // (Not `clamp`, which keeps NaN.)
    #[allow(clippy::manual_clamp)]
    #[inline(always)]
    pub(super) fn byte(&self, c: f32) -> u8 {
        let q = c.max(0.0).min(1.0);
        // The nearest whole number to `q · SRGB_CELLS` (exact), in the low
        // bits of its sum with 2²³, whose last place is 1.
        let cell = ((q * SRGB_CELLS as f32 + 8_388_608.0).to_bits() & 0x1fff) as usize;
        let cell = cell.min(SRGB_CELLS);
        // At most one threshold lies inside a cell (checked when the table
        // is built): the byte is the count below the cell, plus one where
        // the cell's threshold is at or below `q`.
        self.idx[cell] + u8::from(self.next[cell] <= q)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_byte_table_matches_powf() {
        for i in 0..=200_000u32 {
            let c = i as f32 / 100_000.0 - 0.5;
            assert_eq!(srgb_byte(c), to_byte(linear_to_srgb(c)), "{c}");
        }
        for bits in (0..0x3f80_0000u32).step_by(997) {
            let c = f32::from_bits(bits);
            assert_eq!(srgb_byte(c), to_byte(linear_to_srgb(c)), "{c}");
        }
        // Around every cell's edges (halfway values round to even cells).
        for q in 0..=2 * SRGB_CELLS as u32 + 1 {
            let edge = (q as f32 - 1.0) / (2 * SRGB_CELLS) as f32;
            for d in -2i32..=2 {
                let c = f32::from_bits(edge.max(0.0).to_bits().saturating_add_signed(d));
                assert_eq!(srgb_byte(c), to_byte(linear_to_srgb(c)), "{c}");
            }
        }
        // ...and every threshold (the smallest value of each byte).
        for want in 1..=255u8 {
            let lo = srgb_threshold(want).to_bits();
            for d in -2i32..=2 {
                let c = f32::from_bits(lo.saturating_add_signed(d));
                assert_eq!(srgb_byte(c), to_byte(linear_to_srgb(c)), "{c}");
            }
        }
        assert_eq!(srgb_byte(f32::NAN), to_byte(linear_to_srgb(f32::NAN)));
        assert_eq!(srgb_byte(f32::INFINITY), 255);
        assert_eq!(srgb_byte(f32::NEG_INFINITY), 0);
    }

    #[test]
    fn srgb_round_trip() {
        for i in 0..=255u32 {
            let c = i as f32 / 255.0;
            assert_eq!(to_byte(linear_to_srgb(srgb_to_linear(c))), i as u8);
        }
    }
}
