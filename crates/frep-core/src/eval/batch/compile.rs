//! Compiling a tape into the batch evaluator's register program.
//!
//! - Liveness: which varying nodes the outputs need, and each one's last
//!   use.
//! - `sin a` and `cos a` of one argument become one instruction.
//! - Registers are allocated in tape order and freed at their last use;
//!   uniform operands are broadcast once per call.

use super::{Instr, Loc, Program, Src, Trig, LANES};
use crate::graph::{Node, NodeId, Tape};
use crate::ops::UnaryOp;

/// Which nodes the program computes, and the index of each one's last use
/// (`u32::MAX` for outputs, which live to the end).
fn liveness(tape: &Tape, alias: &[u32], loc: &[Loc], outputs: &[NodeId]) -> (Vec<bool>, Vec<u32>) {
    let n = tape.nodes.len();
    let res = |c: NodeId| alias[c.index()] as usize;
    // Needed varying nodes (guards of checks are skipped: `alias` resolves
    // every Check to its value, so guards are never children here).
    let mut needed = vec![false; n];
    for &o in outputs {
        needed[res(o)] = true;
    }
    for i in (0..n).rev() {
        if needed[i] && loc[i] == Loc::Var {
            for c in tape.nodes[i].children() {
                needed[res(c)] = true;
            }
        }
    }
    const KEEP: u32 = u32::MAX;
    let mut last = vec![0u32; n];
    for i in 0..n {
        if needed[i] && loc[i] == Loc::Var {
            for c in tape.nodes[i].children() {
                last[res(c)] = i as u32;
            }
        }
    }
    for &o in outputs {
        last[res(o)] = KEEP;
    }
    (needed, last)
}

/// `sin a` and `cos a` of the same varying `a`, both needed, are computed
/// together where the first of the two comes: `partner[first] = second`.
/// The second is then only a register.
fn sincos_partners(tape: &Tape, alias: &[u32], loc: &[Loc], needed: &[bool]) -> Vec<u32> {
    let n = tape.nodes.len();
    let res = |c: NodeId| alias[c.index()] as usize;
    let mut partner = vec![u32::MAX; n];
    let mut first_of = std::collections::HashMap::new();
    for i in 0..n {
        if !(needed[i] && loc[i] == Loc::Var) || alias[i] as usize != i {
            continue;
        }
        if let Node::Unary(op @ (UnaryOp::Sin | UnaryOp::Cos), a) = tape.nodes[i] {
            let a = res(a);
            if loc[a] != Loc::Var {
                continue;
            }
            let other = if op == UnaryOp::Sin {
                UnaryOp::Cos
            } else {
                UnaryOp::Sin
            };
            match first_of.get(&(other, a)) {
                Some(&f) if partner[f] == u32::MAX => partner[f] = i as u32,
                _ => {
                    first_of.entry((op, a)).or_insert(i);
                }
            }
        }
    }
    partner
}

/// Builds the register program computing `outputs`.
///
/// The main loop is long but one pass: in tape order it allocates each
/// node's register, emits its instruction and frees the operands' registers
/// at their last use. The three steps must interleave, so they stay together.
pub(super) fn compile(tape: &Tape, alias: &[u32], loc: &[Loc], outputs: &[NodeId]) -> Program {
    let n = tape.nodes.len();
    let res = |c: NodeId| alias[c.index()] as usize;
    let (needed, last) = liveness(tape, alias, loc, outputs);
    let mut st = Alloc {
        reg: vec![u32::MAX; n],
        n_regs: 3, // 0, 1, 2: x, y, z
        free: Vec::new(),
        bcast: Vec::new(),
        bcast_of: std::collections::HashMap::new(),
    };
    let partner = sincos_partners(tape, alias, loc, &needed);
    let mut fused = vec![false; n];
    let mut xyz = [false; 3];
    let mut instrs = Vec::new();
    for i in 0..n {
        if !(needed[i] && loc[i] == Loc::Var) || alias[i] as usize != i {
            continue;
        }
        let node = tape.nodes[i];
        if fused[i] {
            // Computed with its partner: free its operand if this was its
            // last use.
            let a = node.children().next().map(res).expect("a unary node");
            if last[a] == i as u32 && !matches!(tape.nodes[a], Node::X(_)) {
                st.free.push(st.reg[a]);
            }
            continue;
        }
        if partner[i] != u32::MAX {
            let (Node::Unary(op, a), j) = (node, partner[i] as usize) else {
                unreachable!("partners are unary")
            };
            let a = res(a);
            let ra = st.reg[a];
            let (d1, d2) = (st.alloc(), st.alloc());
            st.reg[i] = d1;
            st.reg[j] = d2;
            fused[j] = true;
            instrs.push(if op == UnaryOp::Sin {
                Instr::SinCos(d1, d2, ra)
            } else {
                Instr::SinCos(d2, d1, ra)
            });
            if last[a] == i as u32 && !matches!(tape.nodes[a], Node::X(_)) {
                st.free.push(ra);
            }
            continue;
        }
        if let Node::X(k) = node {
            // Varying coordinates are k < 3.
            xyz[k as usize] = true;
            st.reg[i] = k;
            continue;
        }
        let mut opr = |c: NodeId| st.operand(loc, res(c));
        let instr = match node {
            Node::Unary(op, a) => Instr::Unary(op, 0, opr(a)),
            Node::PowI(a, k) => Instr::PowI(0, opr(a), k),
            Node::Select(c, t, e) => Instr::Select(0, [c, t, e].map(opr)),
            Node::Blend(op, args) => Instr::Blend(op, 0, args.map(opr)),
            Node::Binary(op, a, b) => {
                let src = |c: NodeId| {
                    let r = res(c);
                    match loc[r] {
                        Loc::Var => Src::Reg(st.reg[r]),
                        Loc::Uni(u) => Src::Uni(u),
                    }
                };
                Instr::Binary(op, 0, src(a), src(b))
            }
            Node::Const(_) | Node::X(_) | Node::Param(_) | Node::Error(_) | Node::Check(..) => {
                unreachable!("uniform or aliased node")
            }
        };
        // The destination is allocated before the operands are freed, so it
        // never equals an operand register.
        let dst = st.alloc();
        st.reg[i] = dst;
        instrs.push(match instr {
            Instr::Unary(op, _, a) => Instr::Unary(op, dst, a),
            Instr::Binary(op, _, a, b) => Instr::Binary(op, dst, a, b),
            Instr::PowI(_, a, k) => Instr::PowI(dst, a, k),
            Instr::Select(_, o) => Instr::Select(dst, o),
            Instr::Blend(op, _, o) => Instr::Blend(op, dst, o),
            Instr::SinCos(..) => unreachable!("emitted above"),
        });
        // Free the registers of operands used for the last time.
        let mut seen = [usize::MAX; 5];
        for (j, c) in node.children().enumerate() {
            let r = res(c);
            if loc[r] == Loc::Var && last[r] == i as u32 && !seen.contains(&r) {
                seen[j] = r;
                if !matches!(tape.nodes[r], Node::X(_)) {
                    st.free.push(st.reg[r]);
                }
            }
        }
    }
    let Alloc {
        reg, n_regs, bcast, ..
    } = st;
    let outputs = outputs
        .iter()
        .map(|&o| {
            let r = res(o);
            match loc[r] {
                Loc::Var => Src::Reg(reg[r]),
                Loc::Uni(u) => Src::Uni(u),
            }
        })
        .collect();
    Program {
        instrs,
        bcast,
        outputs,
        xyz,
        regs: vec![[0.0; LANES]; n_regs as usize],
        trig: Trig::Exact,
        lines: [None, None, None, None, None, None],
    }
}

/// Register allocation state of [`compile`].
struct Alloc {
    reg: Vec<u32>,
    n_regs: u32,
    free: Vec<u32>,
    bcast: Vec<(u32, u32)>,
    bcast_of: std::collections::HashMap<u32, u32>,
}

impl Alloc {
    fn alloc(&mut self) -> u32 {
        self.free.pop().unwrap_or_else(|| {
            self.n_regs += 1;
            self.n_regs - 1
        })
    }

    /// The register of an operand; a uniform one is broadcast into a
    /// register filled once per call.
    fn operand(&mut self, loc: &[Loc], r: usize) -> u32 {
        match loc[r] {
            Loc::Var => self.reg[r],
            Loc::Uni(u) => {
                if let Some(&b) = self.bcast_of.get(&u) {
                    return b;
                }
                // A fresh register, never freed: one from the free list was
                // used earlier in the program and would be overwritten by
                // the next block.
                let b = self.n_regs;
                self.n_regs += 1;
                self.bcast.push((b, u));
                self.bcast_of.insert(u, b);
                b
            }
        }
    }
}
