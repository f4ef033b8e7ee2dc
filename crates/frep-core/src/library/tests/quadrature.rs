//! Convolution surfaces against quadrature of the Cauchy kernel.

use super::*;

fn kernel(s: f64, r2: f64) -> f64 {
    1.0 / sq(1.0 + s * s * r2)
}

/// Composite Simpson rule of `f` over `[a, b]` with `n` (even) intervals.
fn simpson(f: impl Fn(f64) -> f64, a: f64, b: f64, n: usize) -> f64 {
    let h = (b - a) / n as f64;
    let mut s = f(a) + f(b);
    for i in 1..n {
        s += f(a + i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 };
    }
    s * h / 3.0
}

fn dist2(a: [f64; 3], b: [f64; 3]) -> f64 {
    sq(a[0] - b[0]) + sq(a[1] - b[1]) + sq(a[2] - b[2])
}

fn segment_integral(x: [f64; 3], b: [f64; 3], e: [f64; 3], s: f64) -> f64 {
    let l = dist2(b, e).sqrt();
    simpson(
        |t| {
            let u = t / l;
            let p = [
                b[0] + u * (e[0] - b[0]),
                b[1] + u * (e[1] - b[1]),
                b[2] + u * (e[2] - b[2]),
            ];
            kernel(s, dist2(x, p))
        },
        0.0,
        l,
        4000,
    )
}

const QPTS: [[f64; 3]; 5] = [
    [0.0, 0.0, 0.0],
    [0.3, 0.4, 0.2],
    [-1.1, 0.5, -0.3],
    [0.7, -0.6, 0.9],
    [2.0, 0.1, 0.1],
];

#[test]
fn conv_line_and_curve_match_quadrature() {
    let b = [-1.0, 0.2, 0.0, 0.3, -0.5, 0.4];
    let e = [1.0, -0.1, 0.3, 0.0, 1.0, -0.2];
    let s = [2.0, 1.3];
    for x in QPTS {
        let want: f64 = (0..2)
            .map(|n| segment_integral(x, triple_f(&b, 3 * n), triple_f(&e, 3 * n), s[n]))
            .sum();
        let got = val(
            "hfconvline",
            &[arr(&x), arr(&b), arr(&e), arr(&s), Sc(0.25)],
        );
        assert!(
            close(got, want - 0.25, 1e-6, 1e-9),
            "line at {x:?}: {got} vs {}",
            want - 0.25
        );
        let v = [
            -1.0, 0.0, 0.0, -0.3, 0.5, 0.0, 0.3, -0.5, 0.1, 1.0, 0.0, 0.0,
        ];
        let sc = [2.0, 1.5, 1.0];
        let want: f64 = (0..3)
            .map(|n| segment_integral(x, triple_f(&v, 3 * n), triple_f(&v, 3 * n + 3), sc[n]))
            .sum();
        let got = val("hfconvcurve", &[arr(&x), arr(&v), arr(&sc), Sc(0.0)]);
        assert!(
            close(got, want, 1e-6, 1e-9),
            "curve at {x:?}: {got} vs {want}"
        );
    }
}

fn triple_f(v: &[f64], i: usize) -> [f64; 3] {
    [v[i], v[i + 1], v[i + 2]]
}

/// Rodrigues rotation of `v` about the unit axis `k` by `a` radians.
fn rodrigues(v: [f64; 3], k: [f64; 3], a: f64) -> [f64; 3] {
    let (c, s) = (a.cos(), a.sin());
    let kv = [
        k[1] * v[2] - k[2] * v[1],
        k[2] * v[0] - k[0] * v[2],
        k[0] * v[1] - k[1] * v[0],
    ];
    let kd = k[0] * v[0] + k[1] * v[1] + k[2] * v[2];
    [
        v[0] * c + kv[0] * s + k[0] * kd * (1.0 - c),
        v[1] * c + kv[1] * s + k[1] * kd * (1.0 - c),
        v[2] * c + kv[2] * s + k[2] * kd * (1.0 - c),
    ]
}

#[test]
fn conv_arc_matches_quadrature() {
    let rd = 3.141592 / 180.0;
    // (centre, radius, theta [deg], axis, angle [deg], S)
    let arcs: [([f64; 3], f64, f64, [f64; 3], f64, f64); 4] = [
        ([0.0, 0.0, 0.0], 1.0, 90.0, [0.0, 0.0, 1.0], -1e-6, 2.0),
        ([0.2, -0.1, 0.3], 0.8, 150.0, [1.0, 0.0, 0.0], 45.0, 1.5),
        ([0.0, 0.0, 0.0], 1.2, 270.0, [0.0, 1.0, 1.0], 30.0, 2.0),
        ([0.1, 0.1, 0.0], 0.7, 400.0, [0.0, 0.0, 1.0], 10.0, 1.8),
    ];
    let xs = [
        [0.05, -0.3, 0.2],
        [0.5, 0.6, 0.1],
        [-0.7, 0.3, -0.2],
        [1.1, -0.2, 0.4],
    ];
    for (ci, &(ctr, r, theta, axis, angle, s)) in arcs.iter().enumerate() {
        // the arc's points: c + R(axis', angle') (r cos t, r sin t, 0), t in [0, theta]
        let ang = (angle + 1e-6) * rd;
        let ax = [axis[0] + 1e-6, axis[1] + 1e-6, axis[2] + 1e-6];
        let l = (ax[0] * ax[0] + ax[1] * ax[1] + ax[2] * ax[2]).sqrt();
        let k = [ax[0] / l, ax[1] / l, ax[2] / l];
        let th = theta.min(360.0) * rd;
        for x in xs {
            let want = simpson(
                |t| {
                    let p = rodrigues([r * t.cos(), r * t.sin(), 0.0], k, ang);
                    let p = [p[0] + ctr[0], p[1] + ctr[1], p[2] + ctr[2]];
                    // the C closed form integrates over the angle, not the arc length
                    kernel(s, dist2(x, p))
                },
                0.0,
                th,
                6000,
            );
            let ta = [
                arr(&x),
                arr(&ctr),
                arr(&[r]),
                arr(&[theta]),
                arr(&axis),
                arr(&[angle]),
                arr(&[s]),
                Sc(0.0),
            ];
            let (got, arrays) = run("hfconvarc", &ta);
            assert!(
                close(got, want, 1e-6, 1e-9),
                "arc {ci} at {x:?}: {got} vs {want}"
            );
            // the arrays are updated in place
            assert_eq!(arrays[5], vec![angle + 1e-6]);
            assert_eq!(arrays[3], vec![theta.min(360.0).min(180.0)]);
        }
    }
}

/// Integral of the kernel over the triangle `a b c` (Duffy map, Simpson).
fn triangle_integral(x: [f64; 3], a: [f64; 3], b: [f64; 3], c: [f64; 3], s: f64) -> f64 {
    let e1 = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let e2 = [c[0] - b[0], c[1] - b[1], c[2] - b[2]];
    let cr = [
        e1[1] * e2[2] - e1[2] * e2[1],
        e1[2] * e2[0] - e1[0] * e2[2],
        e1[0] * e2[1] - e1[1] * e2[0],
    ];
    let area2 = (cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]).sqrt();
    simpson(
        |u| {
            u * area2
                * simpson(
                    |v| {
                        let p = [
                            a[0] + u * e1[0] + u * v * e2[0],
                            a[1] + u * e1[1] + u * v * e2[1],
                            a[2] + u * e1[2] + u * v * e2[2],
                        ];
                        kernel(s, dist2(x, p))
                    },
                    0.0,
                    1.0,
                    200,
                )
        },
        0.0,
        1.0,
        200,
    )
}

#[test]
fn conv_triangle_and_mesh_match_quadrature() {
    let tris = [
        [-0.5, 0.0, 0.0, 0.5, 0.0, 0.0, 0.0, 0.8, 0.0],
        [0.3, -0.2, 0.1, -0.4, 0.6, 0.5, 0.2, 0.9, -0.3],
    ];
    let s: [f64; 2] = [1.5, 2.0];
    let all: Vec<f64> = tris.iter().flatten().copied().collect();
    for x in QPTS {
        let mut want = 0.0;
        for (t, &sn) in tris.iter().zip(&s) {
            // The C closed form is S³ times the kernel's area integral.
            want += sn.powi(3)
                * triangle_integral(x, triple_f(t, 0), triple_f(t, 3), triple_f(t, 6), sn);
        }
        let got = val("hfconvtriangle", &[arr(&x), arr(&all), arr(&s), Sc(0.0)]);
        assert!(
            close(got, want, 1e-6, 1e-9),
            "triangle at {x:?}: {got} vs {want}"
        );
        // the same two triangles as a mesh sharing vertex lists
        let verts = all.clone();
        let tri = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0];
        let got_m = val(
            "hfconvmesh",
            &[arr(&x), arr(&verts), arr(&tri), arr(&s), Sc(0.0)],
        );
        assert_eq!(got_m, got);
        // vertex order does not matter (the C code reorders them)
        let rot: Vec<f64> = [&tris[0][3..], &tris[0][..3], &tris[1][6..], &tris[1][..6]].concat();
        let got_r = val("hfconvtriangle", &[arr(&x), arr(&rot), arr(&s), Sc(0.0)]);
        assert!(close(got_r, want, 1e-6, 1e-9));
    }
}

#[test]
fn conv_line_r_is_clamped_and_normalised() {
    // A single segment: f - T is 0 on the segment's surface at distance R
    // from its middle.
    let b = [-1.0, 0.0, 0.0];
    let e = [1.0, 0.0, 0.0];
    let r = 0.5;
    let on = val(
        "hfconvliner",
        &[arr(&[0.0, 0.0, 0.0]), arr(&b), arr(&e), Sc(r)],
    );
    assert!(on > 0.0);
    let far = val(
        "hfconvliner",
        &[arr(&[0.0, 3.0, 0.0]), arr(&b), arr(&e), Sc(r)],
    );
    assert!(far < 0.0);
    // the independent formula with S = 1/R
    let s = 1.0 / r;
    let l: f64 = 2.0;
    let pt = (1.0 + s * s * r * r).sqrt();
    let qt2 = 1.0 + s * s * (r * r + l * l);
    let t = l / (2.0 * pt * pt * qt2) + (s * l / pt).atan() / (2.0 * s * pt * pt * pt);
    let x = [0.3, 0.2, 0.1];
    let d = [x[0] + 1.0, x[1], x[2]];
    let xx = d[0];
    let dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    let p = (1.0 + s * s * (dd - xx * xx)).sqrt();
    let q2 = 1.0 + s * s * (dd + l * l - 2.0 * l * xx);
    let f = xx / (2.0 * p * p * (p * p + s * s * xx * xx))
        + (l - xx) / (2.0 * p * p * q2)
        + ((s * xx / p).atan() + (s * (l - xx) / p).atan()) / (2.0 * s * p * p * p);
    let got = val("hfconvliner", &[arr(&x), arr(&b), arr(&e), Sc(r)]);
    assert_close(got, f.min(1.0) - t);
}
