//! The build script of a glazec user: compile `materials/` into `OUT_DIR`.
//!
//! `glazec::build::Build::run` prints `cargo:rerun-if-changed` for the folder and every
//! material, writes the shaders and `OUT_DIR/glazec_materials.rs`, and fails the build with
//! glazec's diagnostics if a material has errors. The sphere grid is drawn by glazec's own
//! preview pipelines (`Build::harness`); the light-loop scene imports the libraries alone into
//! its own shader, as a host does.
//!
//! It also compiles a second set, `OUT_DIR/layout_cases/`: generated materials whose runtime
//! parameters come in every order of `f32` and `vec3<f32>` up to five members (the awkward
//! cases of WGSL's uniform layout: a vec3 after an f32 starts a new 16-byte slot, an f32 after a
//! vec3 fills its last 4 bytes), for the layout test.

use std::fmt::Write as _;
use std::path::PathBuf;

fn main() {
    // The sphere grid renders through glazec's own preview pipelines: ask for its harness too.
    glazec::build::Build::new("../../materials").harness(true).run();
    light_loop();
    layout_cases();
}

/// The light-loop scene's materials (`OUT_DIR/light_loop/`): two libraries that go into the
/// program's own shader, so each gets bindings of its own in the program's material group 1
/// (group 0 is the program's camera and lights): `tunable_glaze`'s parameters at 1:0 and its
/// tables after them at 1:1. (`wet_clay`'s parameters are all literals: its library binds
/// nothing of its own.)
fn light_loop() {
    use glazec::lower::bindings::{Resource, Slot};
    let out = PathBuf::from(std::env::var_os("OUT_DIR").expect("cargo sets OUT_DIR")).join("light_loop");
    let build = glazec::build::Build::new("../../materials")
        .out_dir(&out)
        .targets(&[glazec::Target::Wgsl])
        .bind_material("tunable_glaze", Resource::Params, Slot::new(1, 0));
    if let Err(e) = build.generate() {
        panic!("the light-loop materials do not compile: {e}");
    }
}

/// Parameter kinds: a scalar (`f32`) or a colour (`vec3<f32>`).
#[derive(Clone, Copy, PartialEq)]
enum Kind {
    Scalar,
    Color,
}

fn layout_cases() {
    let out = PathBuf::from(std::env::var_os("OUT_DIR").expect("cargo sets OUT_DIR")).join("layout_cases");
    let sources = out.join("materials");
    std::fs::create_dir_all(&sources).expect("creates OUT_DIR/layout_cases/materials");
    let mut patterns: Vec<Vec<Kind>> = vec![Vec::new()];
    for _ in 0..5 {
        let longer: Vec<Vec<Kind>> = patterns
            .iter()
            .filter(|p| p.len() == patterns.last().map_or(0, Vec::len))
            .flat_map(|p| [Kind::Scalar, Kind::Color].map(|k| [p.clone(), vec![k]].concat()))
            .collect();
        patterns.extend(longer);
    }
    for pattern in patterns.iter().filter(|p| !p.is_empty()) {
        let name: String = pattern.iter().map(|k| if *k == Kind::Scalar { 's' } else { 'c' }).collect();
        let text = material_text(&format!("layout_{name}"), pattern);
        std::fs::write(sources.join(format!("layout_{name}.ron")), text).expect("writes a layout case");
    }
    if let Err(e) = glazec::build::Build::new(&sources).out_dir(&out).generate() {
        panic!("layout cases do not compile: {e}");
    }
}

/// A stack of coats whose parameters appear in `pattern`'s order. Each coat declares, in order,
/// roughness (f32), IOR (f32), absorption (vec3) and thickness (f32); a slot not needed for the
/// pattern holds a constant, and a kind that no remaining slot of the coat can take opens the
/// next coat.
fn material_text(name: &str, pattern: &[Kind]) -> String {
    const SLOTS: [Kind; 4] = [Kind::Scalar, Kind::Scalar, Kind::Color, Kind::Scalar];
    const CONSTANTS: [&str; 4] = ["0.2", "1.5", "(0.1, 0.2, 0.3)", "0.5"];
    let mut coats: Vec<[Option<String>; 4]> = vec![Default::default()];
    let mut next_slot = 0;
    for (index, kind) in pattern.iter().enumerate() {
        let free = (next_slot..4).find(|&s| SLOTS[s] == *kind);
        let slot = match free {
            Some(slot) => slot,
            None => {
                coats.push(Default::default());
                (0..4).find(|&s| SLOTS[s] == *kind).expect("every kind has a slot")
            }
        };
        let value = if *kind == Kind::Scalar { format!("0.{}", index + 1) } else { format!("(0.{index}, 0.2, 0.3)") };
        let last = coats.len() - 1;
        coats[last][slot] = Some(format!("Param(\"p{index}\", {value})"));
        next_slot = slot + 1;
    }
    let mut text = format!("Material(name: \"{name}\", layers: [\n");
    for coat in &coats {
        let field = |s: usize| coat[s].clone().unwrap_or_else(|| CONSTANTS[s].to_string());
        let _ = writeln!(
            text,
            "    Coat(lobe: Ggx(roughness: {}), ior: {}, absorption: {}, thickness: {}),",
            field(0),
            // An IOR parameter's default must be a plausible IOR.
            coat[1].clone().map_or_else(|| CONSTANTS[1].to_string(), |p| p.replace("0.", "1.")),
            field(2),
            field(3)
        );
    }
    text.push_str("    Lambert(albedo: (0.5, 0.5, 0.5)),\n])\n");
    text
}
