//! The FRep ray caster: a [`TileCaster`] for a compiled HyperFun [`Model`].
//!
//! HyperFun fields are not distance fields, so the caster never steps by the
//! field value. Per tile of the image:
//!
//! 0. **Empty tiles.** The tile's whole frustum over the model box's depth
//!    range is evaluated once with interval arithmetic; where that box is
//!    outside, none of the tile's rays is set up (where the model covers
//!    part of the image, that was most of the cost of the misses).
//!    **Set expressions over quadrics.** Where the model is R-functions,
//!    `min`, `max` and negations over fields of degree at most 2 in the
//!    point or root gaps of one ([`ModelCaster::csg`]), every ray is then solved in closed form
//!    (`csg`): its first hit is the first leaf crossing after which the set
//!    expression holds. Only the rays that fail its checks go on to the
//!    steps below.
//! 1. **Frustum pruning.** The tile's rays are clipped to the model box; the
//!    part of the tile frustum between two depths is enclosed in an
//!    axis-aligned box ([`Frustum::aabb_between_depths`](crate::camera::Frustum::aabb_between_depths)) and the field is
//!    evaluated over it with interval arithmetic. A box that is outside
//!    (negative or NaN throughout) is skipped; a box that is inside throughout
//!    ends every ray still searching there; otherwise the tape is shortened
//!    for the box ([`SimplifyMode::Sign`]) and the box is split, front to
//!    back: first along the depth (interval bisection along the frustum)
//!    until a depth slab is about as deep as the rectangle is wide in pixel
//!    footprints, then into four sub-rectangles and two depth halves, down
//!    to leaves of [`LEAF`]×[`LEAF`] pixels. A leaf's slab is narrowed to
//!    the part that may hold the surface by interval evaluations over
//!    sub-slabs [`ModelCaster::narrow_px`] footprints deep (no node
//!    bookkeeping per sub-slab: one leaf is sampled over the span from the
//!    first to the last sub-slab that is not outside, or to the start of
//!    the first sub-slab inside throughout, where every ray is inside; not
//!    where a ray of the leaf enters the model box behind that depth).
//! 2. **Leaves.** Every unresolved ray of a leaf is sampled at steps of
//!    [`ModelCaster::step_px`] pixel footprints across the slab, all rays of
//!    the leaf in one batch ([`BatchEval`], vectorised across rays, with
//!    `sin` and `cos` to about `2e-14` of the value, not an ulp:
//!    [`ModelCaster::trig`]; in an
//!    orthographic view straight along an axis, as lines:
//!    [`BatchEval::eval_lines`], the transcendental functions of the other
//!    two coordinates once per ray and of the axis one once per depth). The
//!    first sign change (`f >= 0` inside, NaN outside) is bracketed; the
//!    ray is then resolved (searched no further), and its bracket waits
//!    for the end of the tile, where all brackets of one shortened tape are
//!    resolved together (batches of up to a tile's rays, not a leaf's).
//!    First the value and gradient at each bracket's false-position point
//!    (the gradient is the normal's): where one Newton step from there
//!    would move at most 1/64 of a footprint and the slope along the ray
//!    agrees with the bracket's secant slope (no kink or bend inside), that
//!    point is the hit. The other brackets are refined to 1/16 of a
//!    footprint, then one secant step: each step evaluates a pair of depths
//!    just either side of the false-position point (Illinois rule), which
//!    for a smooth field nearly always closes the bracket at once.
//!    **Quadrics in closed form.** Where the tape shortened for a box is
//!    a polynomial of degree 2 in the point ([`Tape::polynomial_degree`]:
//!    a sphere, a cylinder, a cone or an ellipsoid alone in the box), the
//!    field along every ray is a polynomial of degree at most 2 in the
//!    depth: the box is split into leaf-sized rectangles over its whole
//!    slab (the quadrants' interval evaluations drop the rays far from the
//!    surface), and each ray's first crossing is solved in closed form;
//!    where the polynomial is clearly outside 1/8 of a footprint before it
//!    and inside 1/8 after, it is the hit. The same holds for a tape
//!    `k − sqrt(p)` with `p` such a polynomial ([`Tape::root_gap`]: its
//!    values `f` map to `f·(2k − f) = k² − p`, of the same sign). The
//!    quadric's coefficients come from the values and gradients at four
//!    points, once per shortened tape; each ray's polynomial
//!    then comes from them and the hit's normal from the quadric's
//!    gradient: no samples and no gradient evaluation per ray (for a model
//!    with no colours, a leaf's rays at once: the common case, a clear
//!    crossing, in one pass over arrays that vectorises,
//!    [`ModelCaster::quadric_blocks`]; for a model
//!    with attribute colours the normals are evaluated with the colours;
//!    where the four points give no quadric, a value not finite there,
//!    each ray is sampled at its slab's ends and middle instead). The
//!    polynomial holds for the whole ray on that tape, so a later slab of
//!    the ray on the same tape needs nothing new; where it has no crossing
//!    on the rest of the ray either, the whole-ray check of step 4 is made
//!    at once where likely to pay. A ray the closed form leaves unsure (a
//!    graze within rounding of the surface, a value not finite) is sampled
//!    as above. Planes (degree 1) likewise: the plane's coefficients come
//!    from one value and gradient, the box's whole rectangle is taken at
//!    once, and each ray that clearly crosses the plane in its slab gets
//!    its hit there with the plane's normal.
//! 3. **Thin features.** A ray whose samples show no crossing although the
//!    leaf is ambiguous can only hide a feature thinner than a step around a
//!    local maximum of its samples; that segment is checked with one
//!    interval evaluation (a leaf's segments over their hull first, then
//!    over each half of a hull not outside: `TileCtx::check_searches`)
//!    and, if it may hold the surface, sampled at the
//!    midpoints of cells of 1/2^[`ModelCaster::fallback_depth`] of a step or
//!    footprint, whichever is smaller (the cells an interval bisection would
//!    end with), batched. A maximum at the *end* of a slab is not searched at
//!    once: the ray remembers its last samples, and when its next slab
//!    follows on and the field keeps rising, there is nothing to search;
//!    otherwise (a gap, a fall, an inside box with a gap, the end of the
//!    tile) the segment is searched first, with the evaluator it was
//!    sampled with, before anything behind it is used.
//! 4. **Rays along walls.** A ray sampled in
//!    [`ModelCaster::prune_after`] leaf slabs without a crossing (down the
//!    bore of a tube seen along its axis, beside a wall parallel to it:
//!    every frustum box there holds the wall) has the rest of its depth
//!    range checked with one interval evaluation over that segment's box,
//!    on the tape shortened for the tile; where it is outside, the ray is a
//!    miss and is searched no further. The check is made where the slabs
//!    left, weighed by the share of checks that succeeded so far, would
//!    cost more to sample than the check (tape lengths as the measure).
//! 5. **Shading inputs.** Normals are `−∇f/|∇f|`, the gradient by
//!    forward-mode automatic differentiation over the batch evaluator's
//!    program ([`BatchEval::eval_grad`]), all hits of a tile and tape in one
//!    batch on that shortened tape (the one that found the hit at a
//!    false-position point, or right after refinement; the shortened tape
//!    keeps the gradient at the surface); where the gradient vanishes
//!    or is not finite (`(r² − |p|²)³` on its surface), central differences
//!    at ½, 2 and 8 pixel footprints, and failing those the direction back
//!    to the eye. Where the solid is cut by the
//!    model box the normal is the box face's. Attribute colours come from
//!    `s[1..3]` when the model declares `s[]`, evaluated on the attributes'
//!    own tape ([`Model::attribute_tape`]), once for all of a group's hits
//!    where an interval evaluation over their box gives each a single value.
//!
//! Tiles are cast by one worker per thread ([`for_each_dynamic`]), each
//! taking the tiles of its own contiguous share one at a time and then the
//! last tile of the largest share left. Evaluators are never built per
//! pixel: each worker thread keeps (from
//! tile to tile, in a pool of the caster, which hands a thread back its
//! own) the root tape's evaluators and
//! those of every shortened tape met so far, keyed by the interval choices
//! that produced them (a tape is simplified and compiled once, and boxes that
//! shorten to the same tape share it), bounded to a few MiB. Rays, frustum
//! corners and pixel footprints use per-image constants ([`RayMaker`]).
//!
//! One concept a file: `settings` (what to render, errors), `render` (the
//! public render functions, ambient occlusion), `caster` ([`ModelCaster`],
//! its statistics and scratch pool), `scratch` (the per-thread scratch and
//! its evaluator cache), `tile` (one tile's cast, step by step), `rays` (ray
//! setup in lanes), `poly` (the ray polynomial, its roots, the quadric),
//! `closed` and `csg` (tiles in closed form, step 0), `frustum` (frustum
//! subdivision, step 1), `exact` (quadrics and planes in closed form),
//! `leaf` (leaf sampling, step 2; rays along walls, step 4), `search` (the
//! thin-feature search, step 3), `refine` (refinement of brackets) and
//! `normals` (normals and colours, step 5), `section` (the section plane:
//! the model cut by a half-space, the cut face's colour).
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
pub use settings::{RenderError, RenderSettings};

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

/// The largest image the renderer accepts: 16 384 pixels a side and 64
/// megapixels in all.
pub const MAX_SIDE: u32 = 16_384;
/// See [`MAX_SIDE`].
pub const MAX_PIXELS: u64 = 64 << 20;
