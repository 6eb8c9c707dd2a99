use super::super::breaks;
use super::*;
use crate::test_support::Lcg;
use std::f64::consts::PI;

#[test]
fn a_sum_of_shifts_is_the_copies_added_one_by_one() {
    // Tables of orders 3 and 7 on 400-odd panels, copies of runs of every length (none, one
    // panel, across blocks, the whole cycle), with gaps, each copy's runs in increasing
    // p: each panel's doubles are those of adding the copies one after another, the
    // definition the block-wise sum must keep.
    let mut random = Lcg(37);
    for order in [3, 7] {
        let panels = Panels::new(&breaks(vec![0.3, 1.1], 2.0 * PI), order, PI / 200.0);
        let count = panels.count();
        let f: Vec<f64> = panels.phi.iter().map(|p| (3.0 * p).sin() + p).collect();
        let own = MonomialRunning::through(&panels, &f);
        for copies in [0, 1, 4, 13] {
            let mut shifts = Vec::new();
            for _ in 0..copies {
                let mut p = (random.next() * 30.0) as usize;
                while p < count {
                    let longest = count - p;
                    let length = match (random.next() * 5.0) as usize {
                        0 => 1,
                        1 => longest,
                        2 => 0,
                        _ => 1 + (random.next() * longest as f64) as usize,
                    };
                    let q = (random.next() * (count - length + 1) as f64) as usize;
                    let at_edge = (random.next() * 3.0).floor() * 17.25;
                    shifts.push(PanelShift {
                        p,
                        q,
                        count: length,
                        at_edge,
                    });
                    p += length + (random.next() * 3.0) as usize;
                }
            }
            let found = own.sum_of_shifts(&shifts);
            let (n, mut expected) = (order, own.zero_like_for_test());
            for s in &shifts {
                for i in 0..s.count {
                    let (p, q) = (s.p + i, s.q + i);
                    for k in 0..=n {
                        expected.running[p * (n + 1) + k] += own.running[q * (n + 1) + k];
                    }
                    expected.at_edges[p] = (expected.at_edges[p] + own.at_edges[q]) + s.at_edge;
                }
            }
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(
                bits(&found.running),
                bits(&expected.running),
                "{order} {copies}"
            );
            assert_eq!(
                bits(&found.at_edges),
                bits(&expected.at_edges),
                "{order} {copies}"
            );
        }
    }
}

#[test]
fn the_orders_compiled_apart_give_the_doubles_of_the_general_rule() {
    // Each order with its sums in registers (through's dispatch) against the one loop for
    // any order: every coefficient and edge value the same to the bit, on uneven panels and
    // values of both signs.
    for order in 1..=13 {
        let panels = Panels::new(&breaks(vec![0.2, 0.21, 3.0], 2.0 * PI), order, PI / 9.0);
        let f: Vec<f64> = panels
            .phi
            .iter()
            .map(|p| (5.0 * p).cos() * 1e3 - p)
            .collect();
        let (special, general) = (
            MonomialRunning::through(&panels, &f),
            MonomialRunning::through_order::<0, 0>(&panels, &f),
        );
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&special.running), bits(&general.running), "{order}");
        assert_eq!(bits(&special.at_edges), bits(&general.at_edges), "{order}");
    }
}

impl MonomialRunning {
    fn zero_like_for_test(&self) -> Self {
        Self {
            at_edges: vec![0.0; self.at_edges.len()],
            running: vec![0.0; self.running.len()],
            order: self.order,
        }
    }
}
