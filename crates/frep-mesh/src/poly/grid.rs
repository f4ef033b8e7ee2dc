//! The sampling lattice: its geometry ([`Grid`]: cells, bricks, virtual
//! samples on the box faces) and its signs once evaluated ([`Lattice`]).

use frep_core::eval::interval::Interval;

use super::octree::Brick;
use super::settings::{MeshError, MeshSettings, Resolution};
use super::{BRICK, MAX_BRICKS};

/// The sampling lattice.
#[derive(Clone, Debug)]
pub(super) struct Grid {
    pub(super) lo: [f64; 3],
    pub(super) hi: [f64; 3],
    /// Samples (cells) per axis.
    pub(super) n: [i32; 3],
    /// Cell size per axis.
    pub(super) h: [f64; 3],
    /// The octree covers `size³` cells.
    pub(super) size: i32,
    /// Brick side in cells.
    pub(super) brick: i32,
    /// Bricks per axis (`size / brick`).
    pub(super) nb: i32,
}

impl Grid {
    pub(super) fn new(s: &MeshSettings) -> Result<Grid, MeshError> {
        let b = s.bounds;
        let lo = [b[0], b[1], b[2]];
        let hi = [b[3], b[4], b[5]];
        if (0..3).any(|k| !(lo[k].is_finite() && hi[k].is_finite() && hi[k] > lo[k])) {
            return Err(MeshError::InvalidBounds(b));
        }
        let ext = (0..3).map(|k| hi[k] - lo[k]).fold(0.0f64, f64::max);
        let cell = match s.resolution {
            Resolution::Depth(d) => {
                if d > s.limits.max_depth {
                    return Err(MeshError::TooDeep {
                        depth: d as u32,
                        max: s.limits.max_depth,
                    });
                }
                ext / (1u64 << d) as f64
            }
            Resolution::CellSize(c) => {
                if !(c > 0.0 && c.is_finite()) {
                    return Err(MeshError::TooDeep {
                        depth: u32::MAX,
                        max: s.limits.max_depth,
                    });
                }
                c
            }
        };
        let n = [0, 1, 2].map(|k| (((hi[k] - lo[k]) / cell) * (1.0 - 1e-12)).ceil().max(1.0));
        let nmax = n.iter().fold(1.0f64, |a, &b| a.max(b));
        let depth = nmax.log2().ceil().max(0.0) as u32;
        if depth > s.limits.max_depth as u32 {
            return Err(MeshError::TooDeep {
                depth,
                max: s.limits.max_depth,
            });
        }
        let n = n.map(|v| v as i32);
        let size = 1i32 << depth;
        let brick = BRICK.min(size).max(size / MAX_BRICKS);
        Ok(Grid {
            lo,
            hi,
            n,
            h: [0, 1, 2].map(|k| (hi[k] - lo[k]) / n[k] as f64),
            size,
            brick,
            nb: size / brick,
        })
    }

    /// Coordinate of sample `i` along axis `a`; `-1` and `n` are the box faces.
    #[inline]
    pub(super) fn coord(&self, a: usize, i: i32) -> f64 {
        if i < 0 {
            self.lo[a]
        } else if i >= self.n[a] {
            self.hi[a]
        } else {
            self.lo[a] + (i as f64 + 0.5) * self.h[a]
        }
    }

    #[inline]
    pub(super) fn point(&self, p: [i32; 3]) -> [f64; 3] {
        [
            self.coord(0, p[0]),
            self.coord(1, p[1]),
            self.coord(2, p[2]),
        ]
    }

    #[inline]
    pub(super) fn is_virtual(&self, p: [i32; 3]) -> bool {
        (0..3).any(|a| p[a] < 0 || p[a] >= self.n[a])
    }

    /// The interval box of a node of `s³` cells at `o`, grown by one cell, clipped to the box.
    pub(super) fn node_box(&self, o: [i32; 3], s: i32) -> [Interval; 3] {
        [0, 1, 2].map(|a| {
            let lo = self.lo[a] + (o[a] as f64 - 0.5) * self.h[a];
            let hi = self.lo[a] + ((o[a] + s) as f64 + 0.5) * self.h[a];
            Interval::new(lo.max(self.lo[a]), hi.min(self.hi[a]))
        })
    }

    #[inline]
    pub(super) fn brick_id(&self, p: [i32; 3]) -> usize {
        let b = p.map(|c| (c / self.brick) as usize);
        let nb = self.nb as usize;
        b[0] + nb * (b[1] + nb * b[2])
    }

    pub(super) fn is_boundary_brick(&self, id: usize) -> bool {
        let nb = self.nb as usize;
        let b = [id % nb, id / nb % nb, id / (nb * nb)];
        (0..3).any(|a| b[a] == 0 || (b[a] as i32 + 1) * self.brick >= self.n[a])
    }
}

pub(super) const OFFS: [[i32; 3]; 8] = [
    [0, 0, 0],
    [1, 0, 0],
    [0, 1, 0],
    [1, 1, 0],
    [0, 0, 1],
    [1, 0, 1],
    [0, 1, 1],
    [1, 1, 1],
];

pub(super) fn add(p: [i32; 3], q: [i32; 3]) -> [i32; 3] {
    [p[0] + q[0], p[1] + q[1], p[2] + q[2]]
}

/// 20 bits per coordinate (shifted by one so that the virtual layer `-1` fits).
pub(super) fn point_key(p: [i32; 3]) -> u64 {
    ((p[0] + 1) as u64) | ((p[1] + 1) as u64) << 20 | ((p[2] + 1) as u64) << 40
}

/// Canonical signs of every sample: the brick map.
pub(super) struct Lattice<'a> {
    pub(super) grid: &'a Grid,
    /// Per brick: 0 outside, 1 inside, `2 + i` evaluated brick `i`.
    pub(super) map: Vec<u32>,
    pub(super) bricks: Vec<Brick>,
}

pub(super) const OUTSIDE: u32 = 0;

pub(super) const INSIDE: u32 = 1;

impl Lattice<'_> {
    #[inline]
    fn local(&self, p: [i32; 3]) -> usize {
        let b = self.grid.brick;
        let l = p.map(|c| c % b);
        (l[0] + b * (l[1] + b * l[2])) as usize
    }

    #[inline]
    pub(super) fn inside(&self, p: [i32; 3]) -> bool {
        if self.grid.is_virtual(p) {
            return false;
        }
        match self.map[self.grid.brick_id(p)] {
            OUTSIDE => false,
            INSIDE => true,
            k => {
                let l = self.local(p);
                self.bricks[(k - 2) as usize].bits[l / 64] >> (l % 64) & 1 == 1
            }
        }
    }

    /// Sample value (uniform baseline: every real sample is in an evaluated brick).
    pub(super) fn value(&self, p: [i32; 3]) -> f64 {
        match self.map[self.grid.brick_id(p)] {
            OUTSIDE => -1.0,
            INSIDE => 1.0,
            k => self.bricks[(k - 2) as usize]
                .values
                .as_ref()
                .map_or(0.0, |v| v[self.local(p)] as f64),
        }
    }

    pub(super) fn case_at(&self, q: [i32; 3]) -> usize {
        let mut mask = 0;
        for (c, off) in OFFS.iter().enumerate() {
            if self.inside(add(q, *off)) {
                mask |= 1 << c;
            }
        }
        mask
    }

    /// The brick that handles cube `q`.
    pub(super) fn owner(&self, q: [i32; 3]) -> Option<usize> {
        let mut first = None;
        for off in OFFS {
            let p = add(q, off);
            if self.grid.is_virtual(p) {
                continue;
            }
            let id = self.grid.brick_id(p);
            match self.map[id] {
                OUTSIDE => {}
                INSIDE => {
                    if first.is_none() && self.grid.is_boundary_brick(id) {
                        first = Some(id);
                    }
                }
                _ => return Some(id),
            }
        }
        first
    }
}

pub(super) fn norm(v: [f64; 3]) -> [f64; 3] {
    let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    if l > 0.0 && l.is_finite() {
        v.map(|c| c / l)
    } else {
        [0.0; 3]
    }
}

pub(super) fn dist2(a: [f64; 3], b: [f64; 3]) -> f64 {
    (0..3).map(|k| (a[k] - b[k]) * (a[k] - b[k])).sum()
}
