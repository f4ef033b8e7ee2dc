//! Merging the bricks' output into one mesh: marching cubes' shared vertices and dual
//! contouring's vertices joined by key.

use std::collections::hash_map::Entry;

use crate::Mesh;

use super::extract::BrickOut;
use super::grid::norm;
use super::{par_each, par_map, KeyMap};

/// Splits `v` into consecutive chunks of these lengths.
fn split_lens<T>(mut v: &mut [T], lens: impl Iterator<Item = usize>) -> Vec<&mut [T]> {
    let mut out = Vec::new();
    for n in lens {
        let (a, b) = std::mem::take(&mut v).split_at_mut(n);
        out.push(a);
        v = b;
    }
    out
}

/// The merge of marching-cubes bricks (`tris` and `shared`). Each brick gives its vertices
/// in order, then its triangles, renumbered. A vertex on a shared edge comes only from the
/// first brick that has it. Only the shared vertices go through one hash map, in brick
/// order. Numbering and copying run in parallel.
/// One brick's part of [`merge_marching`]: its output, its duplicate shared vertices, the
/// number of its first kept vertex, and then its vertices' new numbers.
struct Job<'a> {
    out: &'a BrickOut,
    dups: &'a [(u32, u32, u32)],
    offset: u32,
    remap: Vec<u32>,
}

/// Numbers each brick's vertices: kept ones in order from its offset, duplicates as the
/// earlier brick numbered them.
fn renumber(jobs: &mut [Job]) {
    par_each(jobs, |j| {
        let n = j.out.positions.len();
        j.remap.reserve_exact(n);
        let (mut next, mut d) = (j.offset, 0);
        for v in 0..n as u32 {
            if j.dups.get(d).is_some_and(|x| x.0 == v) {
                j.remap.push(u32::MAX);
                d += 1;
            } else {
                j.remap.push(next);
                next += 1;
            }
        }
    });
    // The earlier bricks' numbers of the duplicates.
    let fixes: Vec<Vec<u32>> = par_map(jobs, |j| {
        j.dups
            .iter()
            .map(|&(_, b0, v0)| jobs[b0 as usize].remap[v0 as usize])
            .collect()
    });
    for (j, f) in jobs.iter_mut().zip(fixes) {
        for (&(v, _, _), g) in j.dups.iter().zip(f) {
            j.remap[v as usize] = g;
        }
    }
}

/// The shared vertices met before, as (this brick's vertex, earlier brick, its vertex), in
/// the order of each brick's vertices; `ends[b]` ends brick b's.
fn shared_duplicates(outs: &[BrickOut]) -> (Vec<(u32, u32, u32)>, Vec<usize>) {
    let nshared: usize = outs.iter().map(|o| o.shared.len()).sum();
    let mut first: KeyMap<(u32, u32)> =
        KeyMap::with_capacity_and_hasher(nshared, Default::default());
    let mut dups: Vec<(u32, u32, u32)> = Vec::new();
    let mut ends = Vec::with_capacity(outs.len());
    for (b, o) in outs.iter().enumerate() {
        for &(v, key) in &o.shared {
            match first.entry(key) {
                Entry::Vacant(e) => {
                    e.insert((b as u32, v));
                }
                Entry::Occupied(e) => {
                    let (b0, v0) = *e.get();
                    dups.push((v, b0, v0));
                }
            }
        }
        ends.push(dups.len());
    }
    (dups, ends)
}

pub(super) fn merge_marching(outs: &mut [BrickOut], mesh: &mut Mesh, with_colors: bool) {
    let (dups, ends) = shared_duplicates(outs);
    let dup_range = |b: usize| if b == 0 { 0 } else { ends[b - 1] }..ends[b];
    // Each brick's kept vertices are numbered in order from its offset.
    let kept: Vec<usize> = (0..outs.len())
        .map(|b| outs[b].positions.len() - dup_range(b).len())
        .collect();
    let mut offsets = Vec::with_capacity(outs.len());
    let mut total = 0usize;
    for &k in &kept {
        offsets.push(total);
        total += k;
    }
    let mut jobs: Vec<Job> = outs
        .iter()
        .enumerate()
        .map(|(b, o)| Job {
            out: o,
            dups: &dups[dup_range(b)],
            offset: offsets[b] as u32,
            remap: Vec::new(),
        })
        .collect();
    renumber(&mut jobs);
    let base_v = mesh.positions.len();
    let base_t = mesh.triangles.len();
    let ntri: usize = outs.iter().map(|o| o.tris.len()).sum();
    mesh.positions.resize(base_v + total, [0.0; 3]);
    mesh.normals.resize(base_v + total, [0.0; 3]);
    if with_colors {
        mesh.colors.resize(base_v + total, [0.0; 3]);
    }
    mesh.triangles.resize(base_t + ntri, [0; 3]);
    let pos = split_lens(&mut mesh.positions[base_v..], kept.iter().copied());
    let nrm = split_lens(&mut mesh.normals[base_v..], kept.iter().copied());
    let mut col = if with_colors {
        split_lens(&mut mesh.colors[base_v..], kept.iter().copied())
    } else {
        Vec::new()
    };
    col.resize_with(outs.len(), Default::default);
    let tri = split_lens(
        &mut mesh.triangles[base_t..],
        outs.iter().map(|o| o.tris.len()),
    );
    let mut work: Vec<_> = jobs
        .iter()
        .zip(pos)
        .zip(nrm)
        .zip(col)
        .zip(tri)
        .map(|((((j, p), n), c), t)| (j, p, n, c, t))
        .collect();
    par_each(&mut work, |(j, p, n, c, t)| {
        let o = j.out;
        let mut k = 0;
        for (v, &g) in j.remap.iter().enumerate() {
            if g == j.offset + k as u32 {
                p[k] = o.positions[v];
                n[k] = o.normals[v];
                if !c.is_empty() {
                    c[k] = o.colors.get(v).copied().unwrap_or([0.0; 3]);
                }
                k += 1;
            }
        }
        for (dst, src) in t.iter_mut().zip(&o.tris) {
            *dst = src.map(|i| j.remap[i as usize]);
        }
    });
    drop(work);
    drop(jobs);
    for o in outs.iter_mut() {
        *o = BrickOut::default();
    }
}

/// The merge of dual-contouring bricks (`keys`, `aliases`, `triangles`, `quads`): vertices
/// joined by key, a collapsed block's keys mapped to its one vertex, quads split along
/// their flatter diagonal. Consumes `outs`.
pub(super) fn merge_dual(mut outs: Vec<BrickOut>, mesh: &mut Mesh, with_colors: bool) {
    let push_vertex = |mesh: &mut Mesh, o: &BrickOut, v: usize| {
        mesh.positions.push(o.positions[v]);
        mesh.normals.push(o.normals[v]);
        if with_colors {
            mesh.colors
                .push(o.colors.get(v).copied().unwrap_or([0.0; 3]));
        }
        (mesh.positions.len() - 1) as u32
    };
    let nv: usize = outs.iter().map(|o| o.keys.len()).sum();
    let mut index: KeyMap<u32> = KeyMap::with_capacity_and_hasher(nv, Default::default());
    for o in &mut outs {
        for (v, &key) in o.keys.iter().enumerate() {
            if let Entry::Vacant(e) = index.entry(key) {
                e.insert(push_vertex(mesh, o, v));
            }
        }
        o.keys = Vec::new();
        o.positions = Vec::new();
        o.normals = Vec::new();
        o.colors = Vec::new();
    }
    for o in &mut outs {
        for (key, rep) in std::mem::take(&mut o.aliases) {
            if let Some(&i) = index.get(&rep) {
                index.insert(key, i);
            }
        }
    }
    let look = |k: &u64| index.get(k).copied();
    for o in &outs {
        for t in &o.triangles {
            if let [Some(a), Some(b), Some(c)] = t.each_ref().map(look) {
                // Two ends merged by a collapsed block: the triangle is gone.
                if a != b && b != c && c != a {
                    mesh.triangles.push([a, b, c]);
                }
            }
        }
        for q in &o.quads {
            if let [Some(a), Some(b), Some(c), Some(d)] = q.each_ref().map(look) {
                push_quad(mesh, [a, b, c, d]);
            }
        }
    }
}

/// Quad `[a, b, c, d]` as two triangles, or one or none where a collapsed block merged
/// its corners.
fn push_quad(mesh: &mut Mesh, [a, b, c, d]: [u32; 4]) {
    if a == b || b == c || c == d || d == a || a == c || b == d {
        // Around an edge on a collapsed block's face one side is merged: a triangle;
        // inside the block it is gone.
        let mut v = vec![a, b, c, d];
        v.dedup();
        if v.len() > 1 && v[0] == v[v.len() - 1] {
            v.pop();
        }
        if let [x, y, z] = v[..] {
            if x != z {
                mesh.triangles.push([x, y, z]);
            }
        }
        return;
    }
    let p = |i: u32| crate::mesh::to_f64(mesh.positions[i as usize]);
    let tri_n = |x: u32, y: u32, z: u32| {
        norm(crate::mesh::cross(
            crate::mesh::sub(p(y), p(x)),
            crate::mesh::sub(p(z), p(x)),
        ))
    };
    // The diagonal whose two triangles fold least; a zero-area triangle (its normal
    // is 0) makes a split fold most.
    let d1 = crate::mesh::dot(tri_n(a, b, c), tri_n(a, c, d));
    let d2 = crate::mesh::dot(tri_n(a, b, d), tri_n(b, c, d));
    let flat = |x: u32, y: u32, z: u32| tri_n(x, y, z) == [0.0; 3];
    let bad1 = flat(a, b, c) || flat(a, c, d);
    let bad2 = flat(a, b, d) || flat(b, c, d);
    if (d1 >= d2 && !bad1) || bad2 {
        mesh.triangles.push([a, b, c]);
        mesh.triangles.push([a, c, d]);
    } else {
        mesh.triangles.push([a, b, d]);
        mesh.triangles.push([b, c, d]);
    }
}
