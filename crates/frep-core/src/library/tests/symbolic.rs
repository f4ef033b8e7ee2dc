//! Symbolic builds (parameters) agree with constant ones bit for bit.

use super::*;

/// Evaluates node `out` of `g` at the point `x` with parameters `a`.
fn eval(g: &Graph, out: NodeId, x: &[f64], a: &[f64]) -> f64 {
    let mut v = vec![0.0; g.len()];
    for (i, n) in g.nodes().iter().enumerate() {
        let r = match *n {
            Node::Const(_) => Ok(n.const_value().unwrap()),
            Node::X(k) => Ok(x[k as usize]),
            Node::Param(k) => Ok(a[k as usize]),
            Node::Error(e) => Err(e),
            Node::Unary(op, p) => ops::unary(op, v[p.index()]),
            Node::Binary(op, p, q) => ops::binary(op, v[p.index()], v[q.index()]),
            Node::PowI(p, k) => ops::pow_int(v[p.index()], k),
            Node::Select(c, t, e) => Ok(if ops::truthy(v[c.index()]) {
                v[t.index()]
            } else {
                v[e.index()]
            }),
            Node::Blend(op, p) => {
                let w = p.map(|q| v[q.index()]);
                Ok(ops::blend(op, w[0], w[1], w[2], w[3], w[4]))
            }
            Node::Check(_, q) => Ok(v[q.index()]),
        };
        v[i] = r.unwrap_or(f64::NAN);
    }
    v[out.index()]
}

/// Builds `name` with every scalar and array item symbolic (parameters),
/// evaluates it at the values of `ta`, and compares value and arrays with
/// the constant build bit for bit.
fn check_symbolic(name: &str, ta: &[Ta]) {
    let (want, want_arrays) = run(name, ta);
    let mut g = Graph::new();
    let mut params = Vec::new();
    let mut args = Vec::new();
    for t in ta {
        match t {
            Sc(v) => {
                args.push(LibArg::Scalar(g.param(params.len() as u32)));
                params.push(*v);
            }
            Arr(vs) => {
                let mut items = Vec::new();
                for &v in vs {
                    items.push(g.param(params.len() as u32));
                    params.push(v);
                }
                args.push(LibArg::Array(items));
            }
        }
    }
    let f = lookup(name).unwrap();
    let r = (f.build)(&mut g, &mut args).unwrap();
    let got = eval(&g, r, &[], &params);
    assert!(
        got.to_bits() == want.to_bits() || (got.is_nan() && want.is_nan()),
        "{name}: symbolic {got:?} vs constant {want:?}"
    );
    for (a, w) in args.iter().zip(&want_arrays) {
        if let LibArg::Array(items) = a {
            let vals: Vec<f64> = items.iter().map(|&n| eval(&g, n, &[], &params)).collect();
            assert_eq!(&vals, w, "{name}: arrays");
        }
    }
}

#[test]
fn symbolic_builds_match_constant_builds() {
    let c = arr(&[0.1, -0.2, 0.3]);
    for x in PTS.iter().chain(&[[0.3, 0.1, 0.2], [0.12, -0.1, 0.31]]) {
        let xa = arr(x);
        check_symbolic(
            "hfellipsoid",
            &[xa.clone(), c.clone(), Sc(1.0), Sc(0.5), Sc(0.7)],
        );
        check_symbolic(
            "hfellipsoid",
            &[xa.clone(), c.clone(), Sc(1.0), Sc(0.0), Sc(0.7)],
        );
        check_symbolic(
            "hfblock",
            &[xa.clone(), c.clone(), Sc(1.0), Sc(0.5), Sc(0.7)],
        );
        check_symbolic(
            "hfblock",
            &[xa.clone(), c.clone(), Sc(1.0), Sc(-0.5), Sc(0.7)],
        );
        check_symbolic(
            "hfsuperell",
            &[
                xa.clone(),
                c.clone(),
                Sc(1.0),
                Sc(0.5),
                Sc(0.7),
                Sc(0.4),
                Sc(2.5),
            ],
        );
        let cs = [
            arr(&[-0.5, 0.5, 0.0]),
            arr(&[0.0, 0.1, 0.6]),
            arr(&[0.0, 0.1, -0.2]),
        ];
        let mut ta = vec![xa.clone()];
        ta.extend(cs.iter().cloned());
        let mut tm = ta.clone();
        tm.extend([arr(&[1.0, 1.5, 0.8]), arr(&[1.5, 0.3, -2.0]), Sc(0.3)]);
        check_symbolic("hfmetaball", &tm);
        let mut ts = ta.clone();
        ts.extend([arr(&[1.2, 0.7, 1.5]), Sc(0.2)]);
        check_symbolic("hfsoft", &ts);
        for name in ["hftaperx", "hftapery", "hftaperz"] {
            check_symbolic(name, &[xa.clone(), Sc(-0.5), Sc(0.5), Sc(0.0), Sc(2.0)]);
        }
        let sm = [
            arr(&[0.0, 0.0, 1.0]),
            arr(&[0.0, 0.3, 1.5]),
            arr(&[0.5, 0.5, 0.7]),
        ];
        let mut t = vec![xa.clone()];
        t.extend(sm.iter().cloned());
        check_symbolic("hfspacemapcubic", &t);
        check_symbolic("hfspacemapexp", &t);
        check_symbolic(
            "hfa_setcolor",
            &[Sc(x[0]), arr(&[0.0; 3]), Sc(0.1), Sc(0.2), Sc(0.3)],
        );
        for theta in [90.0, 200.0, 500.0] {
            check_symbolic(
                "hfconvarc",
                &[
                    xa.clone(),
                    arr(&[0.1, 0.0, 0.0]),
                    arr(&[0.9]),
                    arr(&[theta]),
                    arr(&[0.0, 1.0, 0.5]),
                    arr(&[20.0]),
                    arr(&[1.7]),
                    Sc(0.1),
                ],
            );
        }
        let tris = [
            0.3, -0.2, 0.1, -0.4, 0.6, 0.5, 0.2, 0.9, -0.3, -0.5, 0.0, 0.0, 0.5, 0.0, 0.0, 0.0,
            0.8, 0.0,
        ];
        check_symbolic(
            "hfconvtriangle",
            &[xa.clone(), arr(&tris), arr(&[1.5, 2.0]), Sc(0.1)],
        );
        check_symbolic(
            "hfconvliner",
            &[
                xa.clone(),
                arr(&[-1.0, 0.0, 0.0]),
                arr(&[1.0, 0.0, 0.0]),
                Sc(0.4),
            ],
        );
    }
}
