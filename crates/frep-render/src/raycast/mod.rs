//! The FRep ray caster: a [`TileCaster`] for a compiled HyperFun [`Model`].
//!
//! HyperFun fields are not distance fields, so the caster never steps by the
//! field value. Per tile of the image:
//!
//! 0. **Empty tiles.** The tile's whole frustum over the model box's depth
//!    range is evaluated once with interval arithmetic. Where that box is
//!    outside, none of the tile's rays is set up. Where the model covers
//!    part of the image, that set-up was most of the cost of the misses.
//!
//!    **Set expressions over quadrics** (`csg`, [`ModelCaster::csg`]). The
//!    model may be R-functions, `min`, `max` and negations over fields of
//!    degree at most 2 in the point, or over root gaps of one. Every ray is
//!    then solved in closed form. Its first hit is the first leaf crossing
//!    after which the set expression holds. Only the rays that fail its
//!    checks go on to the steps below.
//! 1. **Frustum pruning.** The tile's rays are clipped to the model box.
//!    The part of the tile frustum between two depths is enclosed in an
//!    axis-aligned box
//!    ([`Frustum::aabb_between_depths`](crate::camera::Frustum::aabb_between_depths)).
//!    The field is evaluated over that box with interval arithmetic.
//!    - A box outside throughout (negative or NaN) is skipped.
//!    - A box inside throughout ends every ray still searching there.
//!    - Otherwise the tape is shortened for the box
//!      ([`SimplifyMode::Sign`]), and the box is split, front to back.
//!    - It is first bisected along the depth, until a slab is about as deep
//!      as the rectangle is wide in pixel footprints. Then it is split into
//!      four sub-rectangles and two depth halves, down to leaves of
//!      [`LEAF`]×[`LEAF`] pixels.
//!    - A leaf's slab is narrowed to the part that may hold the surface.
//!      Interval evaluations over sub-slabs [`ModelCaster::narrow_px`]
//!      footprints deep find it, with no node bookkeeping per sub-slab.
//!    - The leaf is then sampled over one span: from the first to the last
//!      sub-slab that is not outside. The span ends sooner, at the start of
//!      the first sub-slab inside throughout, since every ray is inside
//!      there. It does not end sooner where a ray of the leaf enters the
//!      model box behind that depth.
//! 2. **Leaves.** Every unresolved ray of a leaf is sampled at steps of
//!    [`ModelCaster::step_px`] pixel footprints across the slab.
//!    - All rays of the leaf go in one batch ([`BatchEval`], vectorised
//!      across rays). Its `sin` and `cos` are within about `2e-14` of the
//!      value, not an ulp ([`ModelCaster::trig`]).
//!    - In an orthographic view straight along an axis, the leaf is sampled
//!      as lines ([`BatchEval::eval_lines`]). The transcendental functions
//!      of the other two coordinates are then computed once per ray, those
//!      of the axis coordinate once per depth.
//!    - The first sign change (`f >= 0` inside, NaN outside) is bracketed.
//!      The ray is then resolved: it is searched no further.
//!    - Its bracket waits for the end of the tile. There, all brackets of
//!      one shortened tape are resolved together, in batches of up to a
//!      tile's rays rather than a leaf's.
//!    - First come the value and gradient at each bracket's false-position
//!      point (the gradient is the normal's). That point is the hit where
//!      one Newton step from it would move at most 1/64 of a footprint, and
//!      the slope along the ray agrees with the bracket's secant slope. The
//!      agreement shows that no kink or bend lies inside.
//!    - The other brackets are refined to 1/16 of a footprint, then take
//!      one secant step. Each step evaluates a pair of depths just either
//!      side of the false-position point (Illinois rule). For a smooth field
//!      that nearly always closes the bracket at once.
//!
//!    **Quadrics in closed form.** The tape shortened for a box may be a
//!    polynomial of degree 2 in the point ([`Tape::polynomial_degree`]).
//!    That is a sphere, a cylinder, a cone or an ellipsoid alone in the
//!    box. The field along every ray is then a polynomial of degree at most
//!    2 in the depth.
//!    - The box is split into leaf-sized rectangles over its whole slab.
//!      The quadrants' interval evaluations drop the rays far from the
//!      surface.
//!    - Each ray's first crossing is solved in closed form. It is the hit
//!      where the polynomial is clearly outside 1/8 of a footprint before it
//!      and inside 1/8 after.
//!    - The same holds for a tape `k − sqrt(p)` with `p` such a polynomial
//!      ([`Tape::root_gap`]). Its values `f` map to `f·(2k − f) = k² − p`,
//!      which has the same sign.
//!    - The quadric's coefficients come from the values and gradients at
//!      four points, once per shortened tape. Each ray's polynomial comes
//!      from them, and the hit's normal from the quadric's gradient. No ray
//!      needs samples or a gradient evaluation of its own.
//!    - For a model with no colours, a leaf's rays are solved at once
//!      ([`ModelCaster::quadric_blocks`]). The common case, a clear
//!      crossing, takes one pass over arrays that vectorises.
//!    - For a model with attribute colours, the normals are evaluated with
//!      the colours.
//!    - The four points may give no quadric, for example where a value there
//!      is not finite. Each ray is then sampled at its slab's ends and
//!      middle instead.
//!    - The polynomial holds for the whole ray on that tape, so a later slab
//!      of the ray on the same tape needs nothing new. Where the ray has no
//!      crossing on the rest of its length either, the whole-ray check of
//!      step 4 is made at once, where it is likely to pay.
//!    - A ray the closed form leaves unsure is sampled as above: a graze
//!      within rounding of the surface, or a value not finite.
//!    - Planes (degree 1) likewise. The plane's coefficients come from one
//!      value and gradient, and the box's whole rectangle is taken at once.
//!      Each ray that clearly crosses the plane in its slab gets its hit
//!      there, with the plane's normal.
//! 3. **Thin features.** A ray's samples may show no crossing although the
//!    leaf is ambiguous. Only a feature thinner than a step can then hide
//!    there, around a local maximum of the samples.
//!    - That segment is checked with one interval evaluation
//!      (`TileCtx::check_searches`). A leaf's segments are checked over
//!      their hull first, then over each half of a hull that is not outside.
//!    - A segment that may hold the surface is sampled, batched, at the
//!      midpoints of cells of 1/2^[`ModelCaster::fallback_depth`] of a step
//!      or a footprint, whichever is smaller. These are the cells an
//!      interval bisection would end with.
//!    - A maximum at the *end* of a slab is not searched at once. The ray
//!      remembers its last samples. When its next slab follows on and the
//!      field keeps rising, there is nothing to search.
//!    - Otherwise the segment is searched first, before anything behind it
//!      is used, with the evaluator it was sampled with. The cases are a
//!      gap, a fall, an inside box with a gap, and the end of the tile.
//! 4. **Rays along walls.** Some rays pass many leaf slabs without a
//!    crossing: down the bore of a tube seen along its axis, or beside a
//!    wall parallel to them. Every frustum box there holds the wall.
//!    - After [`ModelCaster::prune_after`] such slabs, the rest of the ray's
//!      depth range is checked with one interval evaluation over that
//!      segment's box, on the tape shortened for the tile.
//!    - Where that is outside, the ray is a miss and is searched no further.
//!    - The check is made where sampling the slabs left would cost more than
//!      the check, weighed by the share of checks that succeeded so far.
//!      Tape lengths measure the cost.
//! 5. **Shading inputs.** Normals are `−∇f/|∇f|`.
//!    - The gradient comes by forward-mode automatic differentiation over
//!      the batch evaluator's program ([`BatchEval::eval_grad`]).
//!    - All hits of a tile and tape go in one batch, on the shortened tape
//!      that found the hit (at a false-position point, or right after
//!      refinement). The shortened tape keeps the gradient at the surface.
//!    - Where the gradient vanishes or is not finite (`(r² − |p|²)³` on its
//!      surface), central differences at ½, 2 and 8 pixel footprints stand
//!      in. Failing those, the normal is the direction back to the eye.
//!    - Where the solid is cut by the model box, the normal is the box
//!      face's.
//!    - Attribute colours come from `s[1..3]` when the model declares `s[]`.
//!      They are evaluated on the attributes' own tape
//!      ([`Model::attribute_tape`]). Where an interval evaluation over a
//!      group's box gives each a single value, they are evaluated once for
//!      all of the group's hits.
//!
//! Tiles are cast by one worker per thread ([`for_each_dynamic`]). Each
//! worker takes the tiles of its own contiguous share one at a time. Then
//! it takes the last tile of the largest share left.
//!
//! Evaluators are never built per pixel. Each worker thread keeps the root
//! tape's evaluators and those of every shortened tape met so far, from tile
//! to tile. They live in a pool of the caster, which hands a thread back its
//! own. They are keyed by the interval choices that produced them: a tape is
//! simplified and compiled once, and boxes that shorten to the same tape
//! share it. The pool is bounded to a few MiB. Rays, frustum corners and
//! pixel footprints use per-image constants ([`RayMaker`]).
//!
//! One concept a file:
//! - `settings`: what to render, errors.
//! - `render`: the public render functions, ambient occlusion.
//! - `caster`: [`ModelCaster`], its statistics and scratch pool.
//! - `scratch`: the per-thread scratch and its evaluator cache.
//! - `tile`: one tile's cast, step by step.
//! - `rays`: ray setup in lanes.
//! - `poly`: the ray polynomial, its roots, the quadric.
//! - `closed` and `csg`: tiles in closed form (step 0).
//! - `frustum`: frustum subdivision (step 1).
//! - `exact`: quadrics and planes in closed form.
//! - `leaf`: leaf sampling (step 2) and rays along walls (step 4).
//! - `search`: the thin-feature search (step 3).
//! - `refine`: refinement of brackets.
//! - `normals`: normals and colours (step 5).
//! - `section`: the section plane (the model cut by a half-space, the cut
//!   face's colour).
//!
//! [`TileCaster`]: crate::tiles::TileCaster
//! [`Model`]: frep_core::Model
//! [`SimplifyMode::Sign`]: frep_core::simplify::SimplifyMode::Sign
//! [`BatchEval`]: frep_core::eval::batch::BatchEval
//! [`BatchEval::eval_lines`]: frep_core::eval::batch::BatchEval::eval_lines
//! [`Tape::polynomial_degree`]: frep_core::Tape::polynomial_degree
//! [`Tape::root_gap`]: frep_core::Tape::root_gap
//! [`BatchEval::eval_grad`]: frep_core::eval::batch::BatchEval::eval_grad
//! [`Model::attribute_tape`]: frep_core::Model::attribute_tape
//! [`for_each_dynamic`]: crate::tiles::for_each_dynamic
//! [`RayMaker`]: crate::camera::RayMaker

mod caster;
mod closed;
mod csg;
mod exact;
mod frustum;
mod leaf;
mod normals;
mod poly;
mod rays;
mod refine;
mod render;
mod scratch;
mod search;
mod section;
mod settings;
mod tile;

pub use caster::{CastStats, ModelCaster};
pub use render::{render, render_camera, render_hits, render_with};
pub use section::{sectioned_tape, Section, SectionError, SECTION_CAP};
pub use settings::{RenderError, RenderLimits, RenderSettings};

/// An interval evaluation costs about this many point evaluations (in a
/// batch) of the same tape: the weight of a whole-ray check against the
/// samples it may save ([`ModelCaster::prune_after`]). Tuned on the
/// turntable views: 8 rather than 4 saves 1.6 % of android_robot's frame
/// and 1 % of sake_pot's, the other views within 0.3 %.
const INTERVAL_COST: f64 = 8.0;

/// Leaves of the tile subdivision are at most this many pixels wide.
pub const LEAF: u32 = 8;

/// At most this many bisection steps refine a bracketed crossing (then one
/// secant step)...
const REFINE: usize = 8;
/// ...until the bracket is at most this many pixel footprints wide.
const REFINE_PX: f64 = 1.0 / 16.0;
/// A bracket's false-position point is the hit without refinement where a
/// Newton step from it would move at most this many footprints (see
/// [`TileCtx::polish`]).
///
/// [`TileCtx::polish`]: crate::raycast::tile::TileCtx::polish
const POLISH_PX: f64 = 1.0 / 64.0;

/// [`TileCtx::exact`] takes a crossing it computed as the hit where its
/// polynomial is clearly outside this many pixel footprints before it and
/// inside as many after.
///
/// [`TileCtx::exact`]: crate::raycast::tile::TileCtx::exact
const EXACT_BRACKET_PX: f64 = 1.0 / 8.0;

/// Rays per pass of [`TileCtx::quadric_block`] (a leaf's).
///
/// [`TileCtx::quadric_block`]: crate::raycast::tile::TileCtx::quadric_block
const QUAD_BLOCK: usize = (LEAF * LEAF) as usize;

/// The largest image the renderer accepts by default
/// ([`RenderLimits::default`]): 16 384 pixels a side and 64 megapixels in
/// all.
pub const MAX_SIDE: u32 = 16_384;
/// See [`MAX_SIDE`].
pub const MAX_PIXELS: u64 = 64 << 20;
