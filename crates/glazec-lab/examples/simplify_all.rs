//! Prints what `simplify` does to every shipped material under every shipped scene.
fn main() {
    let mut scenes: Vec<_> = std::fs::read_dir("scenes").expect("scenes/").map(|e| e.expect("entry").path()).collect();
    scenes.sort();
    let materials = glazec::project::read(&["materials".into()]).expect("materials");
    for scene_path in scenes {
        let text = std::fs::read_to_string(&scene_path).expect("scene");
        let scene = glazec::check::check_scene(&glazec::parse::parse(&text).expect("parses")).expect("checks");
        for file in &materials {
            let (material, _) = glazec::load(&file.text).expect("material");
            let start = std::time::Instant::now();
            let (_, report) = glazec::simplify::simplify(&material, &scene).expect("simplifies");
            if std::env::var("EXPLAIN").is_ok_and(|v| v == material.name || v == "all") {
                println!("{}", report.markdown(true));
            }
            println!(
                "{:10} {:15} {:4} → {:4} ({:+.0}%) err {:.3}  [{:.1}s] {}",
                scene.name,
                material.name,
                report.full_cost,
                report.simplified_cost,
                100.0 * (report.simplified_cost as f64 / report.full_cost as f64 - 1.0),
                report.final_error,
                start.elapsed().as_secs_f64(),
                report.steps.iter().map(|s| s.change.clone()).collect::<Vec<_>>().join("; ")
            );
        }
    }
}
