//! The port against independent f64 formulas, sentinels, attributes and
//! argument errors.

use super::*;

/// One formula per primitive, one block each: long, but flat.
#[test]
fn simple_primitives_match_spec_formulas() {
    let c = [0.2, -0.3, 0.4];
    for x in PTS {
        let (dx, dy, dz) = (x[0] - c[0], x[1] - c[1], x[2] - c[2]);
        let xa = arr(&x);
        let ca = arr(&c);
        assert_close(
            val("hfsphere", &[xa.clone(), ca.clone(), Sc(1.3)]),
            1.69 - dx * dx - dy * dy - dz * dz,
        );
        assert_close(
            val(
                "hfellipsoid",
                &[xa.clone(), ca.clone(), Sc(1.1), Sc(0.7), Sc(0.5)],
            ),
            1.0 - sq(dx / 1.1) - sq(dy / 0.7) - sq(dz / 0.5),
        );
        let d = [dx, dy, dz];
        for (k, axis) in ["x", "y", "z"].iter().enumerate() {
            let (i, j) = other_axes(k);
            assert_close(
                val(
                    &format!("hfcylinder{axis}"),
                    &[xa.clone(), ca.clone(), Sc(0.8)],
                ),
                0.64 - d[i] * d[i] - d[j] * d[j],
            );
            assert_close(
                val(
                    &format!("hfellcyl{axis}"),
                    &[xa.clone(), ca.clone(), Sc(0.8), Sc(1.6)],
                ),
                1.0 - sq(d[i] / 0.8) - sq(d[j] / 1.6),
            );
            assert_close(
                val(&format!("hfcone{axis}"), &[xa.clone(), ca.clone(), Sc(0.6)]),
                d[k] * d[k] - sq(d[i] / 0.6) - sq(d[j] / 0.6),
            );
            assert_close(
                val(
                    &format!("hfellcone{axis}"),
                    &[xa.clone(), ca.clone(), Sc(0.6), Sc(0.9)],
                ),
                d[k] * d[k] - sq(d[i] / 0.6) - sq(d[j] / 0.9),
            );
            let (big, r0) = (1.2, 0.35);
            let rho = (d[i] * d[i] + d[j] * d[j]).sqrt();
            assert_close(
                val(
                    &format!("hftorus{axis}"),
                    &[xa.clone(), ca.clone(), Sc(big), Sc(r0)],
                ),
                r0 * r0 - dx * dx - dy * dy - dz * dz - big * big + 2.0 * big * rho,
            );
            // distance variants
            let t = 0.6f64.atan();
            assert_close(
                val(
                    &format!("hfdcone{axis}"),
                    &[xa.clone(), ca.clone(), Sc(0.6)],
                ),
                -(rho * t.cos() - d[k].abs() * t.sin()),
            );
            assert_close(
                val(
                    &format!("hfdtorus{axis}"),
                    &[xa.clone(), ca.clone(), Sc(big), Sc(r0)],
                ),
                -(((rho - big).powi(2) + d[k] * d[k]).sqrt() - r0),
            );
        }
        // hfDCylinder: R - distance to the axis line through c along u.
        let u = [0.3, 0.5, -0.2];
        let (cx, cy, cz) = (
            u[1] * (-dz) - u[2] * (-dy),
            u[2] * (-dx) - u[0] * (-dz),
            u[0] * (-dy) - u[1] * (-dx),
        );
        let dist =
            ((cx * cx + cy * cy + cz * cz) / (u[0] * u[0] + u[1] * u[1] + u[2] * u[2])).sqrt();
        assert_close(
            val("hfdcylinder", &[xa.clone(), ca.clone(), arr(&u), Sc(0.9)]),
            0.9 - dist,
        );
        // block with v = c as the min corner
        let (ddx, ddy, ddz) = (1.0, 1.5, 0.7);
        let u = dx * (ddx - dx);
        let w = dy * (ddy - dy);
        let t = dz * (ddz - dz);
        let f = ops::r_inter(ops::r_inter(u, w), t);
        assert_close(
            val(
                "hfblock",
                &[xa.clone(), ca.clone(), Sc(ddx), Sc(ddy), Sc(ddz)],
            ),
            f,
        );
        // superellipsoid
        let (a, b, cc, s1, s2) = (1.0, 0.8, 0.6, 0.5, 1.5);
        let want = 1.0
            - ((dx / a).abs().powf(2.0 / s2) + (dy / b).abs().powf(2.0 / s2)).powf(s2 / s1)
            - (dz / cc).abs().powf(2.0 / s1);
        assert_close(
            val(
                "hfsuperell",
                &[xa.clone(), ca.clone(), Sc(a), Sc(b), Sc(cc), Sc(s1), Sc(s2)],
            ),
            want,
        );
        // noise
        let (amp, freq, ph) = (0.5, 4.0, 1.4);
        let s = [
            (freq * x[0]).sin(),
            (freq * x[1]).sin(),
            (freq * x[2]).sin(),
        ];
        let k = amp / 1.17;
        let sx = amp * s[0] + k * (freq * x[0] / 1.35 + ph * s[2]).sin();
        let sy = amp * s[1] + k * (freq * x[1] / 1.35 + ph * s[0]).sin();
        let sz = amp * s[2] + k * (freq * x[2] / 1.35 + ph * s[1]).sin();
        assert_close(
            val("hfnoiseg", &[xa.clone(), Sc(amp), Sc(freq), Sc(ph)]),
            sx * sy * sz,
        );
    }
}

#[test]
fn sentinels() {
    let x2 = arr(&[0.0, 0.0]);
    let c = arr(&[0.0; 3]);
    for name in ["hfsphere", "hfcylinderx", "hfconez"] {
        assert_eq!(val(name, &[x2.clone(), c.clone(), Sc(1.0)]), SENTINEL);
    }
    assert_eq!(
        val("hfdconex", &[x2.clone(), c.clone(), Sc(1.0)]),
        -11111111111.0
    );
    let x = arr(&[0.1, 0.2, 0.3]);
    assert_eq!(
        val(
            "hfellipsoid",
            &[x.clone(), c.clone(), Sc(1.0), Sc(5e-7), Sc(1.0)]
        ),
        SENTINEL
    );
    assert_eq!(
        val("hfellcylz", &[x.clone(), c.clone(), Sc(-1e-7), Sc(1.0)]),
        SENTINEL
    );
    assert_eq!(
        val(
            "hfblock",
            &[x.clone(), c.clone(), Sc(1.0), Sc(-0.1), Sc(1.0)]
        ),
        SENTINEL
    );
    assert_eq!(
        val(
            "hfsuperell",
            &[
                x.clone(),
                c.clone(),
                Sc(1.0),
                Sc(1.0),
                Sc(1.0),
                Sc(0.0),
                Sc(1.0)
            ]
        ),
        SENTINEL
    );
    let e: &[Ta] = &[];
    let _ = e;
    assert_eq!(
        val(
            "hfblobby",
            &[
                x.clone(),
                arr(&[]),
                arr(&[]),
                arr(&[]),
                arr(&[]),
                arr(&[]),
                Sc(0.1)
            ]
        ),
        SENTINEL
    );
    // a cone with R = 0 is not a sentinel in C: inf/NaN arithmetic
    assert!(val("hfconex", &[x.clone(), c.clone(), Sc(0.0)]).is_infinite());
}

#[test]
fn blob_primitives_match_spec_formulas() {
    let x0 = [-0.5, 0.5, 0.0];
    let y0 = [0.0, 0.1, 0.6];
    let z0 = [0.0, 0.1, -0.2];
    let a = [2.0, 3.0, 2.5];
    let b = [1.0, 1.2, 0.8];
    let d = [1.5, 0.9, -2.0];
    for x in PTS.iter().chain(&[[0.1, 0.05, 0.0], [0.45, 0.3, 0.1]]) {
        let r2 = |i: usize| sq(x[0] - x0[i]) + sq(x[1] - y0[i]) + sq(x[2] - z0[i]);
        let blobby: f64 = (0..3).map(|i| b[i] * (-a[i] * r2(i)).exp()).sum::<f64>() - 0.4;
        let centres = [arr(&x0), arr(&y0), arr(&z0)];
        let mut ta = vec![arr(x)];
        ta.extend(centres.iter().cloned());
        let mut tb = ta.clone();
        tb.extend([arr(&a), arr(&b), Sc(0.4)]);
        assert_close(val("hfblobby", &tb), blobby);
        let mut mb = 0.0;
        for i in 0..3 {
            let r = r2(i).sqrt();
            if d[i] > 0.0 {
                if r <= d[i] / 3.0 {
                    mb += b[i] * (1.0 - 3.0 * sq(r / d[i]));
                } else if r < d[i] {
                    mb += 1.5 * b[i] * sq(1.0 - r / d[i]);
                }
            }
        }
        let mut tm = ta.clone();
        tm.extend([arr(&b), arr(&d), Sc(0.3)]);
        assert_close(val("hfmetaball", &tm), mb - 0.3);
        let ds = [1.2, 0.7, 1.5];
        let mut soft = 0.0;
        for (i, &di) in ds.iter().enumerate() {
            let r = r2(i).sqrt();
            if r <= di {
                soft += 1.0 - 22.0 * r.powi(2) / (9.0 * di.powi(2))
                    + 17.0 * r.powi(4) / (9.0 * di.powi(4))
                    - 4.0 * r.powi(6) / (9.0 * di.powi(6));
            }
        }
        let mut ts = ta.clone();
        ts.extend([arr(&ds), Sc(0.2)]);
        assert!(close(val("hfsoft", &ts), soft - 0.2, 1e-12, 1e-14));
        // conv point
        let pv = [-0.5, 0.0, 0.0, 0.5, 0.2, 0.1];
        let s = [1.5, 2.0];
        let mut f = 0.0;
        for n in 0..2 {
            let r2 = sq(x[0] - pv[3 * n]) + sq(x[1] - pv[3 * n + 1]) + sq(x[2] - pv[3 * n + 2]);
            f += 1.0 / sq(1.0 + s[n] * s[n] * r2);
        }
        assert_close(
            val("hfconvpoint", &[arr(x), arr(&pv), arr(&s), Sc(0.3)]),
            f - 0.3,
        );
    }
}

#[test]
fn transformations_match_spec_formulas() {
    for x in PTS {
        let t = transform(x, "hfscale3d", &[Sc(2.0), Sc(0.5), Sc(4.0)]);
        assert_eq!(t, vec![x[0] / 2.0, x[1] / 0.5, x[2] / 4.0]);
        let t = transform(x, "hfshift3d", &[Sc(2.0), Sc(0.5), Sc(4.0)]);
        assert_eq!(t, vec![x[0] - 2.0, x[1] - 0.5, x[2] - 4.0]);
        let th: f64 = 0.7;
        let (ct, st) = (th.cos(), th.sin());
        let t = transform(x, "hfrotate3dz", &[Sc(th)]);
        assert_eq!(t, vec![x[0] * ct + x[1] * st, -x[0] * st + x[1] * ct, x[2]]);
        let t = transform(x, "hfrotate3dx", &[Sc(th)]);
        assert_eq!(t, vec![x[0], x[1] * ct + x[2] * st, -x[1] * st + x[2] * ct]);
        let t = transform(x, "hfrotate3dy", &[Sc(th)]);
        assert_eq!(t, vec![-x[2] * st + x[0] * ct, x[1], x[2] * ct + x[0] * st]);
        // twist Z
        let tt = (x[2] - -1.0) / (2.0 - -1.0);
        let th = (1.0 - tt) * 0.2 + tt * 1.1;
        let (ct, st) = (th.cos(), th.sin());
        let t = transform(x, "hftwistz", &[Sc(-1.0), Sc(2.0), Sc(0.2), Sc(1.1)]);
        assert_eq!(t, vec![x[0] * ct + x[1] * st, -x[0] * st + x[1] * ct, x[2]]);
        // taper Y (scales z and x)
        let scale = if x[1] < -0.5 {
            0.0
        } else if x[1] > 0.5 {
            2.0
        } else {
            let t = (x[1] + 0.5) / 1.0;
            (1.0 - t) * 0.0 + t * 2.0
        };
        let scale = if scale.abs() < 1e-6 { 1.0 } else { scale };
        let t = transform(x, "hftapery", &[Sc(-0.5), Sc(0.5), Sc(0.0), Sc(2.0)]);
        assert_eq!(t, vec![x[0] / scale, x[1], x[2] / scale]);
        let t = transform(
            x,
            "hfstretch3d",
            &[arr(&[0.1, 0.2, 0.3]), Sc(2.0), Sc(3.0), Sc(0.5)],
        );
        assert_eq!(
            t,
            vec![
                0.1 + (x[0] - 0.1) / 2.0,
                0.2 + (x[1] - 0.2) / 3.0,
                0.3 + (x[2] - 0.3) / 0.5
            ]
        );
        // space maps with two source points
        let src = [0.0, 0.0, 1.0, 1.0, 0.0, 0.0];
        let tgt = [0.0, 0.5, 1.5, 1.2, -0.3, 0.0];
        let bb = [0.5, 0.6, 0.7, 1.0, 1.1, 0.9];
        for cubic in [false, true] {
            let mut p = x;
            for i in [0, 3] {
                let dt = [
                    tgt[i] - src[i],
                    tgt[i + 1] - src[i + 1],
                    tgt[i + 2] - src[i + 2],
                ];
                let u: f64 = (0..3)
                    .map(|k| sq((p[k] - tgt[i + k]) / (bb[i + k] * (1.0 + dt[k].abs()))))
                    .sum();
                let w = if cubic {
                    let r = u.sqrt();
                    if r <= 1.0 {
                        (1.0 - r).powi(3) / (1.0 + r)
                    } else {
                        0.0
                    }
                } else {
                    (-u).exp()
                };
                for k in 0..3 {
                    p[k] -= w * dt[k];
                }
            }
            let name = if cubic {
                "hfspacemapcubic"
            } else {
                "hfspacemapexp"
            };
            let t = transform(x, name, &[arr(&src), arr(&tgt), arr(&bb)]);
            for k in 0..3 {
                assert_close(t[k], p[k]);
            }
        }
    }
}

#[test]
fn attributes() {
    let (r, arrays) = run(
        "hfa_setcolor",
        &[
            Sc(0.5),
            arr(&[9.0, 9.0, 9.0, 9.0]),
            Sc(0.1),
            Sc(0.2),
            Sc(0.3),
        ],
    );
    assert_eq!(r, 1.0);
    assert_eq!(arrays[1], vec![0.1, 0.2, 0.3, 9.0]);
    let (_, arrays) = run(
        "hfa_setcolor",
        &[Sc(0.0), arr(&[9.0; 3]), Sc(0.1), Sc(0.2), Sc(0.3)],
    );
    assert_eq!(arrays[1], vec![0.1, 0.2, 0.3], "f >= 0 sets");
    let (_, arrays) = run(
        "hfa_setcolor",
        &[Sc(-1e-9), arr(&[9.0; 3]), Sc(0.1), Sc(0.2), Sc(0.3)],
    );
    assert_eq!(arrays[1], vec![9.0; 3]);
    let (r, arrays) = run(
        "hfa_setattributes",
        &[Sc(1.0), arr(&[0.0; 3]), arr(&[1.0, 2.0])],
    );
    assert_eq!(r, 1.0);
    assert_eq!(arrays[1], vec![1.0, 2.0, 0.0]);
    let (_, arrays) = run(
        "hfa_setattributes",
        &[Sc(-1.0), arr(&[0.0; 3]), arr(&[1.0, 2.0])],
    );
    assert_eq!(arrays[1], vec![0.0; 3]);
    let e = run_err(
        "hfa_setcolor",
        &[Sc(1.0), arr(&[0.0; 2]), Sc(0.1), Sc(0.2), Sc(0.3)],
    );
    assert_eq!(e.arg, 1);
}

#[test]
fn argument_errors() {
    let x = arr(&[0.1, 0.2, 0.3]);
    let e = run_err("hfsphere", &[x.clone(), arr(&[0.0, 0.0]), Sc(1.0)]);
    assert_eq!(e.arg, 1);
    assert!(e.message.contains("center"), "{}", e.message);
    let e = run_err(
        "hfblobby",
        &[
            x.clone(),
            arr(&[0.0; 3]),
            arr(&[0.0; 3]),
            arr(&[0.0; 2]),
            arr(&[1.0; 3]),
            arr(&[1.0; 3]),
            Sc(0.1),
        ],
    );
    assert_eq!(e.arg, 3);
    let e = run_err(
        "hfconvline",
        &[
            x.clone(),
            arr(&[1.0, 2.0, 3.0]),
            arr(&[1.0, 2.0, 3.0]),
            arr(&[1.0]),
            Sc(0.1),
        ],
    );
    assert!(e.message.contains("same coordinates"), "{}", e.message);
    let e = run_err(
        "hfconvline",
        &[
            x.clone(),
            arr(&[1.0; 3]),
            arr(&[1.0; 2]),
            arr(&[1.0]),
            Sc(0.1),
        ],
    );
    assert_eq!(e.arg, 2);
    let e = run_err("hfscale3d", &[arr(&[1.0, 2.0]), Sc(1.0), Sc(1.0), Sc(1.0)]);
    assert_eq!(e.arg, 0);
    let e = run_err(
        "hfspacemapexp",
        &[x.clone(), arr(&[1.0; 4]), arr(&[1.0; 4]), arr(&[1.0; 4])],
    );
    assert_eq!(e.arg, 1);
    let e = run_err(
        "hfspacemapexp",
        &[x.clone(), arr(&[1.0; 3]), arr(&[1.0; 3]), arr(&[1.0; 2])],
    );
    assert_eq!(e.arg, 3);
    let e = run_err(
        "hfconvmesh",
        &[
            x.clone(),
            arr(&[0.0; 9]),
            arr(&[1.0, 2.0, 4.0]),
            arr(&[1.0]),
            Sc(0.1),
        ],
    );
    assert_eq!(e.arg, 2);
    // symbolic mesh indices
    let mut g = Graph::new();
    let mut args = to_args(
        &mut g,
        &[
            x.clone(),
            arr(&[0.0; 9]),
            arr(&[1.0, 2.0, 3.0]),
            arr(&[1.0]),
            Sc(0.1),
        ],
    );
    if let LibArg::Array(v) = &mut args[2] {
        v[1] = g.param(0);
    }
    let e = (lookup("hfconvmesh").unwrap().build)(&mut g, &mut args).unwrap_err();
    assert!(e.message.contains("constant"));
}
