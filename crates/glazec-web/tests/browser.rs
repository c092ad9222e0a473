//! The playground (web/, built by `scripts/web`) in headless Chromium: `tests/browser/run.mjs`
//! serves it on 127.0.0.1 and drives it with playwright-core over the DevTools protocol, in
//! Debian's `chromium-headless-shell` with SwiftShader's WebGPU adapter. This test gives it the
//! job and judges its report:
//!
//! * a preset renders: the sphere's centre pixel within [`CENTRE_TOLERANCE`] of glazec's CPU
//!   eval for the page's light, the background black where the environment is off;
//! * an edit that breaks the material shows its diagnostic at the right line, with its code,
//!   marked at its span; fixing it renders the same image again;
//! * a parameter slider changes the image;
//! * the compile time of clay in the browser's WebAssembly, printed.
//!
//! Needs `node`, `npm ci --prefix tests/browser`, the browser and the built page (`scripts/test`
//! does all four); without them the test skips with a message, or fails under
//! `GLAZEC_REQUIRE_TOOLS=1` (CI). `GLAZEC_CHROMIUM` names another browser binary;
//! `GLAZEC_WEB_SCREENSHOT=path.png` saves a screenshot of the page (docs/playground.png).

use std::path::{Path, PathBuf};
use std::process::Command;

use glam::Vec3;
use glazec::model::ParamValue;

/// Largest relative error of the centre pixel, per channel, after decoding its 8-bit sRGB.
const CENTRE_TOLERANCE: f32 = 0.02;
/// The brightest channel of the centre pixel is lit to about this much (linear), where 8-bit
/// quantisation costs at most 0.5% of the value.
const CENTRE_TARGET: f32 = 0.8;
/// 8-bit levels the red channel must move when the body's red albedo goes from 0.8 to 0.2.
const SLIDER_MIN_CHANGE: i64 = 20;
/// The canvas (web/index.html) and the page's view: the sphere fills 90% of its height.
const CANVAS: [u32; 2] = [480, 360];
const SPHERE_FILL: f32 = 0.9;
/// The light, in the page's degrees.
const ELEVATION: f32 = 40.0;
const AZIMUTH: f32 = 35.0;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The browser binary: `GLAZEC_CHROMIUM`, or Debian's chromium-headless-shell (the binary itself:
/// /usr/bin/chromium-headless-shell is a shell script that would outlive its browser).
fn chromium() -> Option<PathBuf> {
    if let Ok(path) = std::env::var("GLAZEC_CHROMIUM") {
        return Some(PathBuf::from(path));
    }
    let debian = PathBuf::from("/usr/lib/chromium/chromium-headless-shell");
    debian.exists().then_some(debian)
}

/// What is missing to run the page, if anything.
fn missing() -> Option<String> {
    let root = root();
    if !Command::new("node").arg("--version").output().is_ok_and(|o| o.status.success()) {
        return Some("`node` (apt-get install nodejs npm)".into());
    }
    if !root.join("tests/browser/node_modules/playwright-core/package.json").exists() {
        return Some("the npm package playwright-core (npm ci --prefix tests/browser)".into());
    }
    if chromium().is_none() {
        return Some("the browser (apt-get install --no-install-recommends chromium-headless-shell)".into());
    }
    if !root.join("web/pkg/glazec_web_bg.wasm").exists() || !root.join("web/pkg/presets.js").exists() {
        return Some("the built page (./scripts/web)".into());
    }
    None
}

/// 8-bit sRGB to linear (IEC 61966-2-1).
fn linear(level: i64) -> f32 {
    let s = level as f32 / 255.0;
    if s <= 0.04045 { s / 12.92 } else { ((s + 0.055) / 1.055).powf(2.4) }
}

/// The light's unit direction, as web/render.js computes it.
fn light() -> Vec3 {
    let (e, a) = (ELEVATION.to_radians(), AZIMUTH.to_radians());
    Vec3::new(e.cos() * a.sin(), e.sin(), e.cos() * a.cos())
}

/// The sphere's normal at the centre of pixel (x, y), as the page's harness computes it.
fn normal_at(x: u32, y: u32) -> Vec3 {
    let scale = 1.0 / SPHERE_FILL;
    let aspect = CANVAS[0] as f32 / CANVAS[1] as f32;
    let ndc = [(x as f32 + 0.5) / CANVAS[0] as f32 * 2.0 - 1.0, 1.0 - (y as f32 + 0.5) / CANVAS[1] as f32 * 2.0];
    let p = [ndc[0] * scale * aspect, ndc[1] * scale];
    Vec3::new(p[0], p[1], (1.0 - p[0] * p[0] - p[1] * p[1]).sqrt())
}

/// f(l, v)·max(n·l, 0) of `text`'s material at its defaults, for a view along +z.
fn eval(text: &str, n: Vec3, l: Vec3) -> Vec3 {
    let (material, _) = glazec::load(text).expect("the preset loads");
    let values: Vec<ParamValue> = material.params.iter().map(|p| p.default).collect();
    let (t, b) = n.any_orthonormal_pair();
    let local = |w: Vec3| Vec3::new(w.dot(t), w.dot(b), w.dot(n));
    glazec::eval::brdf(&material, &values, local(l), local(Vec3::Z)) * n.dot(l).max(0.0)
}

fn rgb(report: &serde_json::Value, key: &str) -> [i64; 3] {
    let at = |i: usize| report.pointer(&format!("{key}/{i}")).and_then(|v| v.as_i64()).unwrap_or(-1);
    [at(0), at(1), at(2)]
}

#[test]
fn the_playground_renders_checks_and_recompiles_in_headless_chromium() {
    if let Some(what) = missing() {
        if std::env::var("GLAZEC_REQUIRE_TOOLS").is_ok_and(|v| v == "1") {
            panic!("{what} is missing and GLAZEC_REQUIRE_TOOLS=1");
        }
        eprintln!("SKIPPED: {what} is missing: the playground's browser test does not run");
        return;
    }
    let root = root();
    let preset = std::fs::read_to_string(root.join("materials/tunable_glaze.ron")).expect("reads the preset");
    let clay = std::fs::read_to_string(root.join("materials/clay.ron")).expect("reads clay");
    let textured =
        std::fs::read_to_string(root.join("examples/textures/textured_clay.ron")).expect("reads textured_clay");
    let centre = [CANVAS[0] / 2, CANVAS[1] / 2];
    // Towards the light from the centre: every material reflects something there.
    let lit = [CANVAS[0] / 2 + 40, CANVAS[1] / 2 - 40];
    let unlit = eval(&preset, normal_at(centre[0], centre[1]), light());
    // The light's intensity (its slider's step is 0.1) that lights the centre to the target.
    let intensity = (10.0 * CENTRE_TARGET / unlit.max_element()).round() / 10.0;
    let expected = unlit * intensity;
    let (from, to) = ("Param(\"glaze_roughness\", 0.15)", "Param(\"glaze_roughness\", 1.6)");
    let broken_line =
        preset.lines().position(|l| l.contains(from)).map(|i| i as i64 + 1).expect("the preset's roughness");
    let screenshot = std::env::var("GLAZEC_WEB_SCREENSHOT").ok();
    let job = serde_json::json!({
        "chromium": chromium(),
        "preset": "tunable_glaze",
        "lighting": { "elevation": ELEVATION, "azimuth": AZIMUTH, "intensity": intensity, "environment": 0, "exposure": 1, "tonemap": false },
        "centre": centre,
        "outside": [5, 5],
        "break": { "from": from, "to": to },
        "slider": { "param": "body_albedo", "component": 0, "value": 0.2, "reset": 0.8 },
        "extra": [textured],
        "lit": lit,
        "timing": clay,
        "screenshot": screenshot,
        "screenshot_preset": "tunable_glaze",
    });
    let dir = tempfile::tempdir().expect("a temporary directory");
    let path = dir.path().join("job.json");
    std::fs::write(&path, job.to_string()).expect("writes the job");
    let out = Command::new("node").arg(root.join("tests/browser/run.mjs")).arg(&path).output().expect("runs node");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "run.mjs failed:\n{stdout}\n{}", String::from_utf8_lossy(&out.stderr));
    let report: serde_json::Value = serde_json::from_str(stdout.lines().last().unwrap_or_default())
        .unwrap_or_else(|e| panic!("{e}: {stdout}\n{}", String::from_utf8_lossy(&out.stderr)));
    assert!(
        report["error"].is_null(),
        "the page run failed: {}\n{report:#}",
        report["error"].as_str().unwrap_or_default()
    );
    println!("adapter: {}; page log: {}", report["adapter"], report["log"]);

    // A preset renders: the centre pixel is glazec's CPU eval for the page's light.
    assert_eq!(report["lighting"]["intensity"].as_f64().map(|x| x as f32), Some(intensity), "the page's light");
    let pixel = rgb(&report, "/centre");
    let measured = Vec3::new(linear(pixel[0]), linear(pixel[1]), linear(pixel[2]));
    let error = ((measured - expected).abs() / expected).max_element();
    println!(
        "centre pixel {pixel:?}: linear {measured:.4} vs CPU eval {expected:.4} (light {intensity}): {:.2}%",
        100.0 * error
    );
    assert!(expected.min_element() > 0.05, "the check needs a lit centre: {expected}");
    assert!(
        error <= CENTRE_TOLERANCE,
        "centre pixel {measured} vs CPU {expected}: {:.2}% > {:.0}%",
        100.0 * error,
        100.0 * CENTRE_TOLERANCE
    );
    assert_eq!(rgb(&report, "/outside"), [0, 0, 0], "the background, with the environment off, is black");

    // The broken edit: its diagnostic at the line, with its code, marked at its span.
    let broken = &report["broken"];
    assert_eq!(broken["state"]["state"], "invalid");
    let diagnostics = broken["diagnostics"].as_array().cloned().unwrap_or_default();
    assert_eq!(diagnostics.len(), 1, "{diagnostics:?}");
    assert_eq!(diagnostics[0]["code"], "E0206");
    assert_eq!(diagnostics[0]["line"].as_i64(), Some(broken_line));
    assert_eq!(broken["marks"], serde_json::json!([{ "text": "1.6", "line": broken_line }]));
    assert_eq!(broken["flagged"], serde_json::json!([broken_line]));

    // Fixed: rendered again, the marks gone, the same image.
    let fixed = &report["fixed"];
    assert_eq!(fixed["state"]["state"], "ready");
    assert_eq!(fixed["marks"], 0);
    assert_eq!(rgb(&report, "/fixed/centre"), pixel, "the fixed material draws what the preset drew");

    // Every preset, and the textured clay typed in, renders and lights the sphere.
    let presets = report["presets"].as_object().cloned().unwrap_or_default();
    let shipped = std::fs::read_dir(root.join("materials")).expect("lists materials/");
    let shipped =
        shipped.filter(|e| e.as_ref().is_ok_and(|e| e.path().extension().is_some_and(|x| x == "ron"))).count();
    assert_eq!(presets.len(), shipped + 1, "{:?}", presets.keys());
    for (name, seen) in &presets {
        assert_eq!(seen["state"], "ready", "{name}: {}", seen["status"]);
        let lit = rgb(seen, "/lit");
        assert!(lit.iter().any(|&c| c > 10), "{name}: the sphere is dark where the light falls: {lit:?}");
    }
    println!("{} materials rendered in the browser", presets.len());

    // Presenting through a readback (`?present=readback`) draws the same pixels.
    assert_eq!(report["readback"]["present"], "readback");
    assert_eq!(rgb(&report, "/readback/centre"), pixel, "the readback path's centre pixel");
    assert_eq!(report["preset"]["present"], "canvas", "the main checks draw into the WebGPU canvas");

    // A slider changes the image: less red in the body, the other channels as they were.
    let slid = rgb(&report, "/slider/centre");
    println!("body_albedo.r 0.8 -> 0.2: centre {pixel:?} -> {slid:?}");
    assert!(pixel[0] - slid[0] >= SLIDER_MIN_CHANGE, "{pixel:?} -> {slid:?}");
    assert_eq!(slid[1..], pixel[1..]);

    let timing = &report["timing"];
    println!(
        "clay compiled in the browser's WebAssembly: median {:.1} ms, fastest {:.1} ms over {} runs",
        timing["median_ms"].as_f64().unwrap_or(f64::NAN),
        timing["fastest_ms"].as_f64().unwrap_or(f64::NAN),
        timing["runs"]
    );
}
