//! The seam where the ray caster plugs in. The image is cut into tiles, and
//! tiles run in parallel with rayon. Each tile is cast by a [`TileCaster`],
//! which may prune it with the tile's [`Frustum`] and interval arithmetic.

use std::sync::{Mutex, PoisonError};

use rayon::prelude::*;

use crate::camera::{Camera, Frustum};
use crate::image::{Hit, HitBuffer};

/// A pixel rectangle `[x0, x1) × [y0, y1)` of a `width`×`height` image.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Tile {
    /// Left pixel column (inclusive).
    pub x0: u32,
    /// Top pixel row (inclusive).
    pub y0: u32,
    /// Right pixel column (exclusive).
    pub x1: u32,
    /// Bottom pixel row (exclusive).
    pub y1: u32,
    /// Width of the whole image.
    pub width: u32,
    /// Height of the whole image.
    pub height: u32,
}

impl Tile {
    /// Tile width in pixels.
    pub fn w(&self) -> u32 {
        self.x1 - self.x0
    }

    /// Tile height in pixels.
    pub fn h(&self) -> u32 {
        self.y1 - self.y0
    }

    /// The frustum of this tile's rays.
    pub fn frustum(&self, camera: &Camera) -> Frustum {
        camera.tile_frustum(self.x0, self.y0, self.x1, self.y1, self.width, self.height)
    }
}

/// Cuts a `width`×`height` image into tiles of at most `size`×`size` pixels,
/// row by row from the top-left.
pub fn tiles(width: u32, height: u32, size: u32) -> Vec<Tile> {
    let size = size.max(1);
    let mut out = Vec::new();
    for y0 in (0..height).step_by(size as usize) {
        for x0 in (0..width).step_by(size as usize) {
            out.push(Tile {
                x0,
                y0,
                x1: (x0 + size).min(width),
                y1: (y0 + size).min(height),
                width,
                height,
            });
        }
    }
    out
}

/// Splits a row-major `width`-pixel image buffer (`per_px` elements per
/// pixel) into the rows of each tile of `tiles`. The tiles must be cut as
/// [`tiles`] cuts them: row by row from the top-left, one size. Per tile,
/// it gives its rows' slices, top to bottom. Workers can then write their
/// tiles straight into the image.
///
/// # Panics
/// If `tiles` is not such a cut of a `width`-wide image that `buf` holds.
pub fn tile_rows<'a, T>(
    buf: &'a mut [T],
    width: usize,
    per_px: usize,
    tiles: &[Tile],
) -> Vec<Vec<&'a mut [T]>> {
    let mut out: Vec<Vec<&'a mut [T]>> = tiles
        .iter()
        .map(|t| Vec::with_capacity(t.h() as usize))
        .collect();
    let Some(first) = tiles.first() else {
        return out;
    };
    let size = first.w().max(first.h()).max(1) as usize;
    let across = width.div_ceil(size);
    let rows = buf.len() / (width * per_px).max(1);
    // The cut, checked once per tile (not per row).
    assert!(
        tiles.len() == rows.div_ceil(size) * across
            && tiles.iter().enumerate().all(|(i, t)| {
                let (x0, y0) = (i % across * size, i / across * size);
                (t.x0 as usize, t.y0 as usize) == (x0, y0)
                    && t.x1 as usize == (x0 + size).min(width)
                    && t.y1 as usize == (y0 + size).min(rows)
            }),
        "tile_rows: tiles not cut row by row"
    );
    for (y, row) in buf.chunks_exact_mut(width * per_px).enumerate() {
        let band = &mut out[y / size * across..][..across];
        for (tile, seg) in band.iter_mut().zip(row.chunks_mut(size * per_px)) {
            tile.push(seg);
        }
    }
    out
}

/// Runs `f` on every item of `work`, in parallel on rayon's threads, each
/// worker with its own state from `init`, kept from item to item.
///
/// A tile's cost varies by orders of magnitude: background, surface,
/// silhouette. A parallel iterator hands each thread fixed chunks of the
/// tiles once their number is split down (a quarter of the image each on 2
/// threads). A thread that finishes early then idles.
///
/// Here each worker owns a contiguous share of the items and takes them
/// one at a time from its front. Neighbouring tiles thus stay on one
/// thread, whose caches of shortened tapes serve them. A worker whose share
/// is done takes the last item of the largest share left. The workers
/// finish within one item of each other. A worker that does not start (its
/// thread busy elsewhere) leaves its share to the others.
pub fn for_each_dynamic<W, S>(
    work: Vec<W>,
    init: impl Fn() -> S + Sync,
    f: impl Fn(&mut S, W) + Sync,
) where
    W: Send,
{
    let n = work.len();
    let workers = rayon::current_num_threads().clamp(1, n.max(1));
    // Per worker, the range of items not yet taken from its share.
    let shares: Vec<(usize, usize)> = (0..workers)
        .map(|w| (w * n / workers, (w + 1) * n / workers))
        .collect();
    let items: Vec<Option<W>> = work.into_iter().map(Some).collect();
    let queue = Mutex::new((items, shares));
    (0..workers).into_par_iter().with_max_len(1).for_each(|w| {
        let mut state = init();
        loop {
            // The lock is held only to take an item (its guard dropped
            // before `f` runs; a panic in `f` leaves the others' items).
            let next = {
                let mut q = queue.lock().unwrap_or_else(PoisonError::into_inner);
                let (items, shares) = &mut *q;
                let (a, b) = shares[w];
                let j = if a < b {
                    shares[w].0 += 1;
                    Some(a)
                } else {
                    let most = (0..workers).max_by_key(|&v| shares[v].1 - shares[v].0);
                    most.filter(|&v| shares[v].1 > shares[v].0).map(|v| {
                        shares[v].1 -= 1;
                        shares[v].1
                    })
                };
                j.and_then(|j| items[j].take())
            };
            let Some(item) = next else {
                break;
            };
            f(&mut state, item);
        }
    });
}

/// Something that finds ray hits for a tile of pixels: the ray caster.
pub trait TileCaster: Sync {
    /// Casts the rays of `tile` (pixel centres, see [`Camera::ray`]) and writes
    /// one entry per pixel into `out`, row-major within the tile
    /// (`out.len() == tile.w() * tile.h()`, all `None` on entry).
    fn cast_tile(&self, camera: &Camera, tile: &Tile, out: &mut [Option<Hit>]);
}

impl<F> TileCaster for F
where
    F: Fn(&Camera, &Tile, &mut [Option<Hit>]) + Sync,
{
    fn cast_tile(&self, camera: &Camera, tile: &Tile, out: &mut [Option<Hit>]) {
        self(camera, tile, out)
    }
}

/// Casts a whole image tile by tile, tiles in parallel (rayon), and gathers
/// the hits into a [`HitBuffer`].
pub fn cast_tiled(
    caster: &dyn TileCaster,
    camera: &Camera,
    width: u32,
    height: u32,
    tile_size: u32,
) -> HitBuffer {
    let tiles = tiles(width, height, tile_size);
    let mut buf = HitBuffer::new(*camera, width, height);
    // Each tile is cast into a buffer of the worker's and copied into its
    // rows of the image.
    let rows = tile_rows(&mut buf.hits, width as usize, 1, &tiles);
    let work: Vec<_> = tiles.into_iter().zip(rows).collect();
    for_each_dynamic(work, Vec::new, |out, (t, rows)| {
        out.clear();
        out.resize((t.w() * t.h()) as usize, None);
        caster.cast_tile(camera, &t, out);
        for (row, src) in rows.into_iter().zip(out.chunks_exact(t.w() as usize)) {
            row.copy_from_slice(src);
        }
    });
    buf
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::Aabb;
    use crate::synthetic::{sphere_hits, SphereCaster};
    use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

    #[test]
    fn tiles_cover_the_image_once() {
        let ts = tiles(70, 33, 16);
        assert_eq!(ts.len(), 5 * 3);
        let area: u32 = ts.iter().map(|t| t.w() * t.h()).sum();
        assert_eq!(area, 70 * 33);
        assert_eq!(ts.last().unwrap().x1, 70);
        assert_eq!(ts.last().unwrap().y1, 33);
    }

    /// Tiles that are not [`tiles`]' cut of the buffer (a 35×33 image,
    /// two elements per pixel) are refused: another image's cut, tiles out
    /// of order or missing.
    #[test]
    fn tile_rows_refuses_other_cuts() {
        let mut buf = vec![0u8; 35 * 33 * 2];
        for ts in [
            tiles(35, 32, 16),
            tiles(35, 34, 16),
            tiles(34, 33, 16),
            tiles(36, 33, 8),
            tiles(35, 33, 16).into_iter().rev().collect(),
            tiles(35, 33, 16)[1..].to_vec(),
        ] {
            let cut = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                tile_rows(&mut buf, 35, 2, &ts).len()
            }));
            assert!(cut.is_err(), "{} tiles", ts.len());
        }
        assert_eq!(tile_rows(&mut buf, 35, 2, &tiles(35, 33, 16)).len(), 9);
        assert_eq!(tile_rows(&mut buf, 35, 2, &tiles(35, 33, 8)).len(), 25);
    }

    #[test]
    fn tile_rows_are_the_tiles_pixels() {
        for (w, h, size) in [(70u32, 33u32, 16u32), (8, 8, 8), (9, 1, 4), (1, 5, 2)] {
            let ts = tiles(w, h, size);
            let mut buf: Vec<(u32, u32, u8)> = (0..h)
                .flat_map(|y| (0..w).flat_map(move |x| [(x, y, 0), (x, y, 1)]))
                .collect();
            let rows = tile_rows(&mut buf, w as usize, 2, &ts);
            assert_eq!(rows.len(), ts.len());
            for (t, rows) in ts.iter().zip(rows) {
                assert_eq!(rows.len(), t.h() as usize);
                for (r, row) in rows.into_iter().enumerate() {
                    let want: Vec<(u32, u32, u8)> = (t.x0..t.x1)
                        .flat_map(|x| [(x, t.y0 + r as u32, 0), (x, t.y0 + r as u32, 1)])
                        .collect();
                    assert_eq!(&row[..], &want[..], "{w}x{h}/{size}: tile {t:?} row {r}");
                    for px in row.chunks_mut(2) {
                        px[0].2 = 9;
                    }
                }
            }
            // Every pixel's first element was written once, through its tile.
            assert!(buf.chunks(2).all(|p| p[0].2 == 9 && p[1].2 == 1));
        }
    }

    #[test]
    fn dynamic_work_is_done_once_each() {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(3)
            .build()
            .unwrap();
        let done: Vec<AtomicUsize> = (0..100).map(|_| AtomicUsize::new(0)).collect();
        let inits = AtomicUsize::new(0);
        pool.install(|| {
            for_each_dynamic(
                (0..100).collect(),
                || inits.fetch_add(1, Ordering::Relaxed),
                |_, i: usize| {
                    done[i].fetch_add(1, Ordering::Relaxed);
                },
            )
        });
        assert!(done.iter().all(|d| d.load(Ordering::Relaxed) == 1));
        // One state per worker, not per item.
        assert!((1..=3).contains(&inits.load(Ordering::Relaxed)));
        for_each_dynamic(Vec::<usize>::new(), || (), |_, _| unreachable!());
    }

    /// While one worker is held up on an item, the others take every other
    /// item. A parallel iterator would leave the held item's chunk-mates
    /// waiting behind it: a quarter of them on 2 threads.
    #[test]
    fn dynamic_work_goes_round_a_slow_item() {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap();
        let n = 64;
        let others = AtomicUsize::new(0);
        let waited = AtomicBool::new(false);
        pool.install(|| {
            for_each_dynamic(
                (0..n).collect(),
                || (),
                |_, i: usize| {
                    if i == 0 {
                        // Held until the rest are done (or, if they never
                        // are meanwhile, 20 s: the test then fails).
                        let t = std::time::Instant::now();
                        while others.load(Ordering::SeqCst) < n - 1 {
                            if t.elapsed().as_secs() >= 20 {
                                return;
                            }
                            std::thread::yield_now();
                        }
                        waited.store(true, Ordering::SeqCst);
                    } else {
                        others.fetch_add(1, Ordering::SeqCst);
                    }
                },
            )
        });
        assert!(
            waited.load(Ordering::SeqCst),
            "the other worker took the rest"
        );
    }

    #[test]
    fn tiled_cast_equals_per_pixel_cast() {
        let b = Aabb::new([-1.0; 3], [1.0; 3]);
        let cam = Camera::orbit(&b, 20.0, 30.0, Some(40.0));
        let caster = SphereCaster {
            center: [0.1, 0.0, 0.0],
            radius: 0.7,
            color: None,
        };
        let tiled = cast_tiled(&caster, &cam, 45, 37, 8);
        let direct = sphere_hits(&cam, 45, 37, [0.1, 0.0, 0.0], 0.7, None);
        assert_eq!(tiled.hits, direct.hits);
        assert!(tiled.hit_count() > 100);
    }
}
