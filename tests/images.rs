//! Rendered images against the reference, compared with ꟻLIP (`glazec images`,
//! `glazec_lab::images`; docs/accuracy.md, "Images").
//!
//! The published figures (`docs/results/images.md`) take minutes to render on two cores, so the
//! deep tier re-renders one material and checks that its figures are the published ones.

mod common;

use glazec_gpu::preview::Image;
use glazec_lab::images;

/// How far a re-rendered ꟻLIP figure may lie from the published one (absolute): the figures are
/// printed to 10⁻³, and lavapipe and the seeded reference render the same pixels again.
const FIGURE_TOL: f64 = 1.5e-3;
/// The material the deep tier re-renders.
const RERENDERED: &str = "wet_clay";

#[test]
fn flip_sees_a_difference_and_nothing_where_there_is_none() {
    let size = 32;
    let grey = Image { width: size, height: size, rgb: vec![128; (size * size * 3) as usize] };
    let mut spotted = grey.clone();
    for px in spotted.rgb.chunks_exact_mut(3).take((size * size / 2) as usize) {
        px.copy_from_slice(&[200, 90, 60]);
    }
    let everywhere = vec![true; (size * size) as usize];
    let (_, same_mean, same_p99) = images::flip(&grey, &grey, &everywhere);
    assert_eq!((same_mean, same_p99), (0.0, 0.0));
    let (map, mean, p99) = images::flip(&grey, &spotted, &everywhere);
    assert!(mean > 0.1 && p99 > mean, "ꟻLIP of a half-coloured image: mean {mean}, p99 {p99}");
    assert_eq!((map.width, map.height), (size, size));
}

/// The figures of one row of `docs/results/images.md`: per lighting, mean, p99 and the noise
/// floor's mean and p99.
fn figures(row: &str) -> Vec<f64> {
    row.split('|')
        .skip(3)
        .flat_map(|cell| cell.split(|c: char| !(c.is_ascii_digit() || c == '.')))
        .filter_map(|t| t.parse().ok())
        .collect()
}

#[test]
fn the_published_figures_reproduce() {
    if !common::deep() {
        eprintln!("the published ꟻLIP figures are re-rendered in the deep tier (GLAZEC_DEEP=1)");
        return;
    }
    let Some(gpu) = common::open_gpu() else { return };
    let sets = images::run(&gpu, Some(RERENDERED), &|_| {}).unwrap_or_else(|e| panic!("{e}"));
    let fresh = sets
        .iter()
        .flat_map(|s| s.markdown().lines().map(String::from).collect::<Vec<_>>())
        .find(|l| l.contains(&format!("| {RERENDERED} |")));
    let published =
        std::fs::read_to_string(common::root().join("docs/results/images.md")).expect("docs/results/images.md");
    let published = published.lines().find(|l| l.contains(&format!("| {RERENDERED} |"))).expect("a published row");
    let (fresh, published) = (figures(&fresh.expect("a rendered row")), figures(published));
    assert_eq!(fresh.len(), 8, "{fresh:?}");
    for (f, p) in fresh.iter().zip(&published) {
        assert!((f - p).abs() <= FIGURE_TOL, "{RERENDERED}: rendered {fresh:?}, published {published:?}");
    }
}
