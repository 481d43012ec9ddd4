//! The contact forces of a coupled step: the small system `B f = r` over the tyres
//! (docs/physics.md section 9), split into independent groups and solved with an active
//! set for unilateral contact.
//!
//! `B_jk = delta_jk + alpha_j . Z_k + kappa_j G_jk`: the bridge term couples tyres on the
//! span, the vehicle term tyres of one vehicle block. A block off the span is solved with
//! its precomputed inverse `D_b^-1 = (I + kappa G)^-1`. The group of tyres coupled through
//! the bridge is `B = D + E S E^T` (D block-diagonal over the vehicle blocks, S the bridge
//! term among the s tyres on the span, E their selection), solved through an s x s system
//! (see `solve_bridge_group`) rather than the whole group's.

use super::{ContactLaw, CoupledSolver, MAX_TYRES_PER_BLOCK};

/// Contacts of one group: `(group key, contact index)`, sorted by contact index.
type Members = [((usize, usize, usize), usize)];

/// One vehicle block's tyres in a group: places `start .. start + tyres` of the members,
/// of which `on[on_first .. on_end]` are on the span.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct BlockRun {
    vehicle: usize,
    block: usize,
    start: usize,
    tyres: usize,
    on_first: usize,
    on_end: usize,
}

impl CoupledSolver<'_> {
    /// Solves the small system for the dynamic tyre forces, with an active set for
    /// unilateral contact. The system falls apart into independent groups (every tyre
    /// coupled through the bridge, then each vehicle block off the span on its own), each
    /// solved alone: a long train off the span costs many 4 x 4 solves, not one large one.
    pub(super) fn solve_contact_forces(&mut self) {
        let p = self.contacts.len();
        self.forces.resize(p, 0.0);
        self.group_contacts();
        let order = std::mem::take(&mut self.order);
        for _iteration in 0..20 {
            // Inactive rows pin f_j = -F_static (zero total force).
            for (j, contact) in self.contacts.iter().enumerate() {
                self.forces[j] = match contact.active {
                    true => contact.rhs,
                    false => -contact.static_load_n,
                };
            }
            for members in order.chunk_by(|a, b| a.0 == b.0) {
                self.solve_group(members);
            }
            if self.contact_law == ContactLaw::Full || !self.update_active_set() {
                break;
            }
        }
        self.order = order;
    }

    /// Sorts the contacts by group: 0 every tyre coupled through the bridge (a vehicle
    /// block with any tyre on the span), then one group per other block, then moving
    /// forces alone.
    /// The order is rebuilt only when it can change: when the blocks on the span or the
    /// vehicles on the road change (a few times per crossing, not every step).
    fn group_contacts(&mut self) {
        let mut blocks = std::mem::take(&mut self.bridge_blocks);
        blocks.clear();
        for c in &self.contacts {
            if let (true, Some((b, _))) = (c.on_span, c.block) {
                blocks.push((c.vehicle, b));
            }
        }
        blocks.sort_unstable();
        blocks.dedup();
        let unchanged = self.on_road == self.grouped_on_road
            && blocks == self.grouped_blocks
            && self.order.len() == self.contacts.len();
        self.bridge_blocks = blocks;
        if unchanged {
            return;
        }
        self.grouped_on_road.clone_from(&self.on_road);
        self.grouped_blocks.clone_from(&self.bridge_blocks);
        self.order.clear();
        for (j, c) in self.contacts.iter().enumerate() {
            let key = match c.block {
                Some((b, _)) if self.bridge_blocks.binary_search(&(c.vehicle, b)).is_ok() => {
                    (0, 0, 0)
                }
                Some((b, _)) => (1, c.vehicle, b),
                None => (2, j, 0),
            };
            self.order.push((key, j));
        }
        self.order.sort_unstable();
    }

    /// Matrix B_jk = delta_jk + alpha_j . Z_k + kappa_j G_jk (same vehicle block) over the
    /// group's contacts; `forces` holds the right-hand side and receives the solution.
    fn solve_group(&mut self, members: &Members) {
        let m = members.len();
        if m == 1 && self.contacts[members[0].1].kappa == 0.0 {
            return; // a moving force: identity row
        }
        if self.solve_off_span(members) || self.solve_bridge_group(members) {
            return;
        }
        let mut entries = std::mem::take(&mut self.entries);
        self.fill_group_matrix(members, &mut entries);
        self.group_rhs.clear();
        self.group_rhs
            .extend(members.iter().map(|&(_, j)| self.forces[j]));
        self.lu
            .solve(m, |i, j| entries[i + j * m], &mut self.group_rhs);
        for (&(_, j), &f) in members.iter().zip(&self.group_rhs) {
            self.forces[j] = f;
        }
        self.entries = entries;
    }

    /// A whole vehicle block off the span with every tyre touching: its precomputed
    /// inverse ([`CoupledVehicle::solve_off_span`]). False when the group is another kind.
    fn solve_off_span(&mut self, members: &Members) -> bool {
        let ((kind, vehicle, block), _) = members[0];
        if kind != 1 {
            return false; // the key of another group kind names no vehicle block
        }
        let v = &self.vehicles[vehicle];
        let m = members.len();
        let whole = m <= MAX_TYRES_PER_BLOCK && m == v.block_tyres(block);
        // Contacts of a vehicle are gathered axle by axle, as the block's tyre places.
        let in_order = members
            .iter()
            .enumerate()
            .all(|(place, &(_, j))| self.contacts[j].block == Some((block, place)));
        if !whole || !in_order || members.iter().any(|&(_, j)| !self.contacts[j].active) {
            return false;
        }
        if v.is_resting(block) {
            return true; // zero right-hand sides, zero forces (already in `forces`)
        }
        let mut forces = [0.0; MAX_TYRES_PER_BLOCK];
        for (f, &(_, j)) in forces.iter_mut().zip(members) {
            *f = self.forces[j];
        }
        v.solve_off_span(block, &mut forces[..m]);
        for (&f, &(_, j)) in forces.iter().zip(members) {
            self.forces[j] = f;
        }
        true
    }

    /// The group coupled through the bridge, `B = D + E S E^T`, when every tyre touches
    /// and every block's `D_b^-1` is known, by the push-through identity: with
    /// `y = D^-1 r` and `g = E^T f` (the forces on the span),
    /// `(I + C S) g = E^T y` where `C = E^T D^-1 E`, then `f = y - D^-1 E S g`. The dense
    /// solve is of the size of the tyres on the span (about 14 for a train over three
    /// 30 m spans) instead of every tyre of the blocks that reach it (about 20). False
    /// (and nothing changed) when the group does not have that shape.
    fn solve_bridge_group(&mut self, members: &Members) -> bool {
        if members[0].0 .0 != 0 || !self.block_runs(members) {
            return false;
        }
        let mut runs = std::mem::take(&mut self.runs);
        let mut on = std::mem::take(&mut self.on_span_places);
        self.find_runs(members, &mut runs, &mut on);
        let s = on.len();
        // y = D^-1 r, block by block.
        let mut y = std::mem::take(&mut self.group_rhs);
        y.clear();
        y.extend(members.iter().map(|&(_, j)| self.forces[j]));
        for run in &runs {
            let (v, t) = (&self.vehicles[run.vehicle], run.tyres);
            v.solve_off_span(run.block, &mut y[run.start..run.start + t]);
        }
        // S (s x s, row-major): S_ab = alpha_a . Z_b.
        let mut bridge = std::mem::take(&mut self.bridge_terms);
        bridge.clear();
        for &pa in &on {
            let alpha = &self.contacts[members[pa].1].alpha;
            bridge.extend(
                on.iter()
                    .map(|&pb| alpha.dot(&self.contacts[members[pb].1].z)),
            );
        }
        // I + C S (row-major): C_ac is D^-1 of a's block between a and c (the tyres of
        // that block on the span are a run of `on`), 0 across blocks, so row a is e_a plus
        // a few rows of S.
        let mut entries = std::mem::take(&mut self.entries);
        entries.clear();
        entries.resize(s * s, 0.0);
        let mut g = std::mem::take(&mut self.push_through);
        g.clear();
        for ((a, &pa), row) in on.iter().enumerate().zip(entries.chunks_exact_mut(s)) {
            g.push(y[pa]);
            row[a] = 1.0;
            let run = &runs[self.run_of[pa]];
            let v = &self.vehicles[run.vehicle];
            for c in run.on_first..run.on_end {
                let d_ac = v.contact_inverse(run.block, pa - run.start, on[c] - run.start);
                for (e, &s_cb) in row.iter_mut().zip(&bridge[c * s..(c + 1) * s]) {
                    *e += d_ac * s_cb;
                }
            }
        }
        self.lu.solve(s, |i, j| entries[i * s + j], &mut g);
        // f = y - D^-1 E (S g).
        let mut load = std::mem::take(&mut self.load_on_span);
        load.clear();
        load.extend(
            (bridge.chunks_exact(s)).map(|row| row.iter().zip(&g).map(|(s, g)| s * g).sum::<f64>()),
        );
        for run in &runs {
            let v = &self.vehicles[run.vehicle];
            for p in run.start..run.start + run.tyres {
                let mut f = y[p];
                for c in run.on_first..run.on_end {
                    f -= v.contact_inverse(run.block, p - run.start, on[c] - run.start) * load[c];
                }
                self.forces[members[p].1] = f;
            }
        }
        self.group_rhs = y;
        self.on_span_places = on;
        self.runs = runs;
        self.bridge_terms = bridge;
        self.entries = entries;
        self.push_through = g;
        self.load_on_span = load;
        true
    }

    /// The block runs of `members` (see [`Self::block_runs`]) and the places of the tyres
    /// on the span (`on`, ascending); `run_of[p]` is the run of place p.
    fn find_runs(&mut self, members: &Members, runs: &mut Vec<BlockRun>, on: &mut Vec<usize>) {
        runs.clear();
        on.clear();
        self.run_of.clear();
        let mut p = 0;
        while p < members.len() {
            let c = &self.contacts[members[p].1];
            let (block, _) = c.block.unwrap_or_default();
            let tyres = self.vehicles[c.vehicle].block_tyres(block);
            let on_first = on.len();
            on.extend((p..p + tyres).filter(|&q| self.contacts[members[q].1].on_span));
            self.run_of.extend(std::iter::repeat_n(runs.len(), tyres));
            runs.push(BlockRun {
                vehicle: c.vehicle,
                block,
                start: p,
                tyres,
                on_first,
                on_end: on.len(),
            });
            p += tyres;
        }
    }

    /// Whether `members` is whole vehicle blocks, each a run of its tyres in place order,
    /// every tyre touching and every block's inverse known.
    fn block_runs(&self, members: &Members) -> bool {
        let mut expected = None;
        members.iter().all(|&(_, j)| {
            let c = &self.contacts[j];
            let Some((block, place)) = c.block else {
                return false;
            };
            let v = &self.vehicles[c.vehicle];
            let t = v.block_tyres(block);
            let ok = c.active
                && t <= MAX_TYRES_PER_BLOCK
                && match expected {
                    Some(e) => e == (c.vehicle, block, place),
                    None => place == 0,
                };
            expected = (place + 1 < t).then_some((c.vehicle, block, place + 1));
            ok
        }) && expected.is_none()
    }

    /// `entries` (m x m, column-major) = B over the group's contacts: `B_jk = delta_jk +`
    /// [`Self::coupling`]`(j, k)` for a row j in contact (not a moving force), else the
    /// identity row. Built column by column: each bridge influence vector Z_k is read by
    /// the rows on the span only, and the vehicle terms are added for the pairs that share
    /// a block.
    fn fill_group_matrix(&self, members: &Members, entries: &mut Vec<f64>) {
        let m = members.len();
        entries.clear();
        entries.resize(m * m, 0.0);
        // Rows that carry the coupling: in contact and not a moving force.
        let live = |j: usize| self.contacts[j].active && self.contacts[j].kappa != 0.0;
        for (col, &(_, k)) in members.iter().enumerate() {
            let column = &mut entries[col * m..(col + 1) * m];
            column[col] = 1.0;
            let ck = &self.contacts[k];
            if !ck.on_span {
                continue;
            }
            for (row, &(_, j)) in members.iter().enumerate() {
                if self.contacts[j].on_span && live(j) {
                    column[row] += self.contacts[j].alpha.dot(&ck.z);
                }
            }
        }
        for (row, &(_, j)) in members.iter().enumerate() {
            let cj = &self.contacts[j];
            let (Some((block, tj)), true) = (cj.block, live(j)) else {
                continue;
            };
            let vehicle = &self.vehicles[cj.vehicle];
            for (col, &(_, k)) in members.iter().enumerate() {
                let ck = &self.contacts[k];
                if let (Some((bk, tk)), true) = (ck.block, ck.vehicle == cj.vehicle) {
                    if bk == block {
                        entries[row + col * m] += cj.kappa * vehicle.block_coupling(block, tj, tk);
                    }
                }
            }
        }
    }

    /// alpha_j . Z_k + kappa_j G_jk: how much a unit dynamic force on tyre k changes tyre
    /// j's force law, through the bridge and through its own vehicle block.
    fn coupling(&self, j: usize, k: usize) -> f64 {
        let (cj, ck) = (&self.contacts[j], &self.contacts[k]);
        let mut entry = 0.0;
        if cj.on_span && ck.on_span {
            entry += cj.alpha.dot(&ck.z);
        }
        if let (Some((bj, tj)), Some((bk, tk))) = (cj.block, ck.block) {
            if cj.vehicle == ck.vehicle && bj == bk {
                entry += cj.kappa * self.vehicles[cj.vehicle].block_coupling(bj, tj, tk);
            }
        }
        entry
    }

    /// Flips contacts whose state is inconsistent with the solution; true if any changed.
    fn update_active_set(&mut self) -> bool {
        let mut changed = false;
        for j in 0..self.contacts.len() {
            let f_trial = self.trial_force(j);
            let contact = &self.contacts[j];
            let axle = &self.vehicles[contact.vehicle].dynamics.axles[contact.axle];
            if axle.dof.is_none() {
                continue;
            }
            let total = axle.static_load_n + f_trial;
            let should_touch = total > 0.0;
            if should_touch != contact.active {
                self.contacts[j].active = should_touch;
                changed = true;
            }
        }
        changed
    }

    /// The tyre force law evaluated at the current solution (what the tyre would carry in contact).
    fn trial_force(&self, j: usize) -> f64 {
        let contact = &self.contacts[j];
        if !contact.active {
            let v = &self.vehicles[contact.vehicle];
            if v.dynamics.axles[contact.axle].dof.is_none() {
                return 0.0;
            }
            // u = u0 - Z f, y = y0 + W f: the law's linear form at that state.
            let mut value = contact.rhs;
            for k in 0..self.contacts.len() {
                value -= self.coupling(j, k) * self.forces[k];
            }
            return value;
        }
        self.forces[j]
    }
}
