use super::*;
use crate::collision::body::sphere;
use crate::collision::proximity::{Reach, unique_edges};

/// A 70 x 70 sheet (1 cm cells) lying 1-3 mm over the top of a 30 cm sphere, falling
/// 2 mm onto it.
fn sheet_on_a_sphere() -> (Vec<Vec3>, Vec<Aabb>, Vec<[u32; 3]>, Vec<Vec3>) {
    let (x, tris, pattern) = sheet_over_a_sphere(70);
    let boxes = x
        .iter()
        .map(|&p| Aabb::point(p).with(p - Vec3::Y * 0.002).grown(0.0005))
        .collect();
    (x, boxes, tris, pattern)
}

/// [`sheet_on_a_sphere`] with a second layer over part of it, so that cloth pairs come
/// too: the first ten rows folded back 3 mm over the rows under them.
fn folded_sheet_on_a_sphere() -> (Vec<Vec3>, Vec<Aabb>, Vec<[u32; 3]>, Vec<Vec3>) {
    let (mut x, mut boxes, tris, pattern) = sheet_on_a_sphere();
    for j in 0..10 {
        for i in 0..70 {
            let k = j * 70 + i;
            x[k] = x[(19 - j) * 70 + i] + Vec3::Y * 0.003;
            boxes[k] = Aabb::point(x[k]).with(x[k] - Vec3::Y * 0.002).grown(0.0005);
        }
    }
    (x, boxes, tris, pattern)
}

/// Every pair of `p` by [`key`], in order.
fn sorted(p: &Proximity) -> Vec<(u8, [u32; 4], [i64; 4])> {
    let mut k: Vec<_> = p.pairs.iter().map(key).collect();
    k.sort_unstable();
    k
}

/// A pair without its energy, comparable: kind, vertices, and the rest to 1e-6.
fn key(q: &Pair) -> (u8, [u32; 4], [i64; 4]) {
    let r = |f: f32| (f as f64 * 1e6).round() as i64;
    (
        q.kind as u8,
        q.v,
        [r(q.n.x), r(q.n.y), r(q.n.z), r(q.delta + q.offset + q.w[1])],
    )
}

#[test]
fn an_update_finds_what_a_full_search_would() {
    let body = sphere(Vec3::ZERO, 0.3, 3).expect("a sphere");
    let (mut x, mut boxes, tris, pattern) = folded_sheet_on_a_sphere();
    let edges = unique_edges(&tris);
    let free = vec![true; x.len()];
    let params = ProximityParams::for_tests(2, Some(-0.5));
    let mut prox = Proximity::default();
    let (x0, b0) = (x.clone(), boxes.clone());
    let mesh = (tris.as_slice(), edges.as_slice());
    let before = ClothView::unwelded((&x0, &b0), mesh, &pattern, &free);
    prox.detect(&before, Some(&body), &params);
    // Some vertices move (in the layer and on the sphere) and get new boxes.
    let mut moved = vec![false; x.len()];
    for k in (0..x.len()).filter(|k| k % 37 == 0 || (k / 70 == 15 && k % 70 < 30)) {
        moved[k] = true;
        x[k] += Vec3::new(0.001, -0.0015, 0.0005);
        boxes[k] = Aabb::point(x[k]).with(x[k] - Vec3::Y * 0.004).grown(0.001);
    }
    let now = ClothView::unwelded((&x, &boxes), mesh, &pattern, &free);
    prox.update(&now, Some(&body), &params, &moved, |_| {});
    let mut full = Proximity::default();
    full.detect(&now, Some(&body), &params);
    assert!(full.counts.vertex_face > 100 && full.counts.edge_edge > 100);
    assert!(full.counts.body_corner_face > 100 && full.counts.floor == 0);
    assert_eq!(sorted(&prox), sorted(&full));
    // The energy is given out alike: once per vertex and feature, once per corner and
    // edge.
    assert_eq!(prox.counts, full.counts);
    for i in [0, 15 * 70 + 3, 2000, x.len() - 1] {
        assert_eq!(prox.roles(i).len(), full.roles(i).len(), "vertex {i}");
    }
    // Another body, or none: a full search.
    prox.update(&now, None, &params, &moved, |_| {});
    full.detect(&now, None, &params);
    assert_eq!(sorted(&prox), sorted(&full));
}

/// Few vertices renewed: the list is changed in place, update after update (places left
/// over filled from the end, vertices that outgrow their room given more), and it stays
/// what a full search of the same boxes finds, each vertex's pairs with it.
#[test]
fn updates_in_place_find_what_a_full_search_would() {
    let body = sphere(Vec3::ZERO, 0.3, 3).expect("a sphere");
    let (mut x, mut boxes, tris, pattern) = folded_sheet_on_a_sphere();
    let edges = unique_edges(&tris);
    let free = vec![true; x.len()];
    let params = ProximityParams::for_tests(2, Some(-0.5));
    let mesh = (tris.as_slice(), edges.as_slice());
    let mut prox = Proximity::default();
    let first = ClothView::unwelded((&x, &boxes), mesh, &pattern, &free);
    prox.detect(&first, Some(&body), &params);
    let (mut relocated, mut grew) = (0, 0);
    for round in 0..6 {
        // A row of the folded layer and a scatter over the sheet, their boxes grown
        // (more pairs) in the even rounds and shrunk in the odd ones.
        let mut moved = vec![false; x.len()];
        let picked = |k: &usize| {
            (k + 13 * round).is_multiple_of(101) || (k / 70 == 2 + round && k % 70 < 25)
        };
        for k in (0..x.len()).filter(picked) {
            moved[k] = true;
            x[k] += Vec3::new(0.0005, -0.001, 0.0);
            let fall = if round % 2 == 0 { 0.005 } else { 0.0005 };
            boxes[k] = Aabb::point(x[k]).with(x[k] - Vec3::Y * fall).grown(0.001);
        }
        let before = prox.pairs.len();
        let now = ClothView::unwelded((&x, &boxes), mesh, &pattern, &free);
        let kept = prox.update(&now, Some(&body), &params, &moved, |_| {
            panic!("listed again")
        });
        assert!(kept, "round {round}: few moved, changed in place");
        relocated += prox.changed().relocated.len();
        grew += usize::from(prox.pairs.len() > before);
        let mut full = Proximity::default();
        full.detect(&now, Some(&body), &params);
        assert_eq!(sorted(&prox), sorted(&full), "round {round}");
        assert_eq!(
            prox.counts, full.counts,
            "round {round}: the energy given alike"
        );
        for i in 0..x.len() {
            assert_eq!(
                prox.roles(i).len(),
                full.roles(i).len(),
                "round {round}, vertex {i}"
            );
            for &r in prox.roles(i) {
                let q = &prox.pairs[(r / 4) as usize];
                assert_eq!(q.v[(r % 4) as usize], i as u32, "round {round}, vertex {i}");
            }
        }
    }
    assert!(
        relocated > 0 && grew > 0,
        "{relocated} moved from the end, {grew} grew"
    );
}

#[test]
fn what_is_done_beside_the_indexing_sees_the_final_pairs() {
    // Boxes of 8 mm round 1 cm cells: enough pairs for the second thread.
    let body = sphere(Vec3::ZERO, 0.3, 3).expect("a sphere");
    let (x, tris, pattern) = sheet_over_a_sphere(70);
    let boxes: Vec<Aabb> = x.iter().map(|&p| Aabb::point(p).grown(0.004)).collect();
    let edges = unique_edges(&tris);
    let free = vec![true; x.len()];
    let cloth = ClothView::unwelded((&x, &boxes), (&tris, &edges), &pattern, &free);
    let search = |threads: usize| {
        let params = ProximityParams::for_tests(threads, None);
        let mut prox = Proximity::default();
        let mut seen = (Vec::new(), Reach::default());
        prox.detect_with(&cloth, Some(&body), &params, |pairs| {
            seen.0 = pairs.to_vec();
            seen.1.compute(pairs, &x);
        });
        (prox, seen)
    };
    let (one, (seen_one, reach_one)) = search(1);
    let (two, (seen_two, reach_two)) = search(2);
    assert!(
        two.pairs.len() >= FINISH_PARALLEL_FROM,
        "{}",
        two.pairs.len()
    );
    // Given the pairs as they are kept, energies and all, on either path.
    assert_eq!(seen_one, one.pairs);
    assert_eq!(seen_two, two.pairs);
    assert_eq!(one.pairs, two.pairs);
    assert_eq!(one.counts, two.counts);
    for i in (0..x.len()).step_by(97) {
        assert_eq!(one.roles(i), two.roles(i), "vertex {i}");
        let t = x[i] + Vec3::Y * 1e-4;
        assert_eq!(
            reach_one.in_reach(i, t),
            reach_two.in_reach(i, t),
            "vertex {i}"
        );
    }
}

#[test]
fn the_body_search_is_the_same_on_any_number_of_threads() {
    let body = sphere(Vec3::ZERO, 0.3, 3).expect("a sphere");
    let (x, boxes, tris, pattern) = sheet_on_a_sphere();
    let edges = unique_edges(&tris);
    let free = vec![true; x.len()];
    let cloth = ClothView::unwelded((&x, &boxes), (&tris, &edges), &pattern, &free);
    let search = |threads: usize| {
        let params = ProximityParams::for_tests(threads, None);
        let mut prox = Proximity::default();
        prox.detect(&cloth, Some(&body), &params);
        (prox.pairs, prox.counts)
    };
    let (pairs, counts) = search(1);
    assert!(
        counts.body_vertex_face > 100
            && counts.body_edge_edge > 100
            && counts.body_corner_face > 100,
        "{counts:?}"
    );
    // The same corner of the sphere against one cloth edge, found from both its
    // triangles, carries one energy.
    let corner_pairs = pairs.iter().filter(|q| q.side == [1, 1, 1, 0]);
    assert!(corner_pairs.clone().any(|q| q.energy));
    assert!(corner_pairs.clone().any(|q| !q.energy));
    for threads in [2, 3] {
        let (many, many_counts) = search(threads);
        assert_eq!(counts, many_counts, "{threads} threads");
        assert_eq!(pairs, many, "{threads} threads");
    }
    assert!(pairs.iter().all(|q| q.holds(&x, 1e-6)));
}
