//! The benchmark models M1–M4 built in fidget, exactly as the anchor figures
//! of `shared/notes/rendering-and-meshing.md` were measured: **negative
//! inside** (fidget's convention; HyperFun's is the opposite), box `[-1, 1]³`.
//!
//! The HyperFun versions (positive inside) are `examples/m1_sphere.hf` …
//! `examples/m4_rblend10.hf`; a frep field `f` should equal `-anchor` there.

use fidget::context::Tree;

/// A benchmark model: its short name (used in benchmark ids) and its field.
pub struct Model {
    /// `"M1"` … `"M4"`.
    pub name: &'static str,
    /// What it is, in a few words.
    pub description: &'static str,
    /// The field, negative inside.
    pub tree: Tree,
}

/// All four models, in order.
pub fn all() -> Vec<Model> {
    vec![
        Model {
            name: "M1",
            description: "sphere",
            tree: m1_sphere(),
        },
        Model {
            name: "M2",
            description: "min of 100 spheres",
            tree: m2_spheres100(),
        },
        Model {
            name: "M3",
            description: "gyroid in a sphere",
            tree: m3_gyroid(),
        },
        Model {
            name: "M4",
            description: "R-union chain of 10 spheres",
            tree: m4_rblend10(),
        },
    ]
}

fn length(x: Tree, y: Tree, z: Tree) -> Tree {
    (x.square() + y.square() + z.square()).sqrt()
}

/// M1: `sqrt(x² + y² + z²) − 0.8`.
pub fn m1_sphere() -> Tree {
    length(Tree::x(), Tree::y(), Tree::z()) - 0.8
}

/// M2: the minimum over a 5 × 5 × 4 lattice of spheres of radius 0.2,
/// centres `(−0.72 + 0.36a, −0.72 + 0.36b, −0.54 + 0.36c)`.
pub fn m2_spheres100() -> Tree {
    let (x, y, z) = Tree::axes();
    let mut field: Option<Tree> = None;
    for a in 0..5 {
        for b in 0..5 {
            for c in 0..4 {
                let cx = -0.72 + 0.36 * a as f32;
                let cy = -0.72 + 0.36 * b as f32;
                let cz = -0.54 + 0.36 * c as f32;
                let sphere = length(x.clone() - cx, y.clone() - cy, z.clone() - cz) - 0.2;
                field = Some(match field {
                    None => sphere,
                    Some(f) => f.min(sphere),
                });
            }
        }
    }
    // The loops above always run, so the fold has a first element.
    field.expect("100 spheres")
}

/// M3: `max(sin 8x cos 8y + sin 8y cos 8z + sin 8z cos 8x, |p| − 0.9)`.
pub fn m3_gyroid() -> Tree {
    let (x, y, z) = Tree::axes();
    let (sx, sy, sz) = ((x.clone() * 8.0), (y.clone() * 8.0), (z.clone() * 8.0));
    let gyroid = sx.sin() * sy.cos() + sy.sin() * sz.cos() + sz.sin() * sx.cos();
    gyroid.max(length(x, y, z) - 0.9)
}

/// The R-union in negative-inside form: `a + b − √(a² + b²)`
/// (HyperFun's `|`, `f1 + f2 + √(f1² + f2²)`, with both operands negated).
pub fn r_union(a: Tree, b: Tree) -> Tree {
    a.clone() + b.clone() - (a.square() + b.square()).sqrt()
}

/// M4: the left-nested R-union chain of ten spheres of radius 0.25 on a helix,
/// `s_i = |p − p_i|² − 0.25²`, `p_i = (0.6 cos 0.6i, 0.6 sin 0.6i, −0.8 + 0.16i)`.
pub fn m4_rblend10() -> Tree {
    let (x, y, z) = Tree::axes();
    let sphere = |i: usize| {
        let t = 0.6 * i as f32;
        let (px, py, pz) = (0.6 * t.cos(), 0.6 * t.sin(), -0.8 + 0.16 * i as f32);
        (x.clone() - px).square() + (y.clone() - py).square() + (z.clone() - pz).square()
            - 0.25 * 0.25
    };
    (1..10).fold(sphere(0), |f, i| r_union(f, sphere(i)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use fidget::shape::EzShape;
    use fidget::vm::VmShape;

    fn value(tree: &Tree, p: [f32; 3]) -> f32 {
        let shape = VmShape::from(tree.clone());
        let tape = shape.ez_point_tape();
        let mut eval = VmShape::new_point_eval();
        let (v, _trace) = eval
            .eval(&tape, p[0], p[1], p[2])
            .expect("point evaluation");
        v
    }

    #[test]
    fn signs_at_known_points() {
        assert!((value(&m1_sphere(), [0.0; 3]) + 0.8).abs() < 1e-6);
        assert!(value(&m1_sphere(), [0.9, 0.0, 0.0]) > 0.0);
        // A lattice centre is inside M2; a point 0.31 from its nearest centres is not.
        assert!((value(&m2_spheres100(), [-0.72, -0.72, -0.54]) + 0.2).abs() < 1e-6);
        assert!(value(&m2_spheres100(), [-0.18, -0.18, 0.0]) > 0.0);
        // Outside the clipping sphere M3 is positive whatever the gyroid does.
        assert!(value(&m3_gyroid(), [0.95, 0.0, 0.0]) > 0.0);
        // The centre of s_0 is inside M4, the origin is outside.
        assert!(value(&m4_rblend10(), [0.6, 0.0, -0.8]) < 0.0);
        assert!(value(&m4_rblend10(), [0.0, 0.0, 0.0]) > 0.0);
    }
}
