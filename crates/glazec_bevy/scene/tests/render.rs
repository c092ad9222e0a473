//! Bevy renders glazec materials with its own lights, and the pixels are glazec's BRDF: a sphere of
//! `tunable_glaze` (runtime parameters) beside one of `coated_gold` over a floor of `clay`, one
//! directional light, no tonemapping, rendered headless on the Vulkan adapter (lavapipe in CI).
//!
//! * Every lit sphere pixel away from the silhouette equals glazec's CPU `eval` × the light's
//!   illuminance × the camera's exposure, with the normal and the view direction of that pixel
//!   from the geometry (the camera's ray through the pixel centre hits the sphere).
//! * A parameter changed on the Bevy material changes the next frame, to the CPU's new value.
//! * The floor where the sphere's shadow falls is darker with the light's shadow maps on, and
//!   lit again when the floor is a `NotShadowReceiver`.
//! * Under a uniform environment map alone, a pixel is the material's directional albedo (the
//!   sum of its image-based-lighting lobes' weights, from the CPU) × the environment's radiance.
//! * Under a point light alone (Bevy's clustered lights), a pixel is `eval` × the light's
//!   intensity × Bevy's inverse-square falloff and range cut-off; under a spot light, × its cone.
//!
//! Without an adapter the test fails when `GLAZEC_REQUIRE_GPU` is set (CI) and skips with a
//! message otherwise.

use bevy::camera::Exposure;
use bevy::core_pipeline::tonemapping::{DebandDither, Tonemapping};
use bevy::light::GlobalAmbientLight;
use bevy::prelude::*;
use glazec_bevy_scene::materials::{clay::Clay, coated_gold::CoatedGold, tunable_glaze::TunableGlaze};
use glazec_bevy_scene::{Headless, pixel};

/// A rendered pixel may differ from the CPU's value by this fraction (the 2%): the 8-bit
/// sRGB target's rounding (≤ 0.7% above a linear 0.15), the tessellated sphere's interpolated
/// normals and f32 evaluation in the shader.
const RELATIVE_TOLERANCE: f32 = 0.02;
/// Pixels are compared where every channel of the expected value is at least this bright (the
/// rounding of an 8-bit code is a larger fraction of darker values) and below clipping.
const DARKEST: f32 = 0.15;
const BRIGHTEST: f32 = 0.92;
/// Pixels count as lit and inside the silhouette where n·l and n·v are at least this.
const MIN_COSINE: f32 = 0.25;
/// The least number of pixels each comparison must find.
const MIN_PIXELS: usize = 200;
/// The floor in the sphere's shadow must be at most this fraction of the unshadowed floor.
const SHADOWED_AT_MOST: f32 = 0.5;
/// The floor where the shadow is looked for must be at least this bright without shadows.
const FLOOR_LIT: f32 = 0.05;

const WIDTH: u32 = 480;
const HEIGHT: u32 = 360;
const ILLUMINANCE: f32 = 2000.0;
const SPHERE_X: [f32; 2] = [-1.2, 1.2];
/// The point light of the last step: its power (lm) and range (m).
const POINT_LUMENS: f32 = 150_000.0;
const POINT_RANGE: f32 = 20.0;
/// The spot light of the last step, from the point light's place: its inner and outer angles
/// (rad), so that the cone's edge crosses the sphere.
const SPOT_ANGLES: (f32, f32) = (0.12, 0.32);

fn adapter_or_skip() -> bool {
    // Vulkan is Bevy's only backend on Linux here; an ICD file says whether one can be had.
    let icds = ["/usr/share/vulkan/icd.d", "/etc/vulkan/icd.d"];
    let found = icds.iter().any(|d| std::fs::read_dir(d).is_ok_and(|mut e| e.next().is_some()));
    if !found {
        assert!(
            std::env::var_os("GLAZEC_REQUIRE_GPU").is_none(),
            "GLAZEC_REQUIRE_GPU is set but no Vulkan driver is installed"
        );
        eprintln!("SKIPPED: no Vulkan driver (install mesa-vulkan-drivers for lavapipe)");
    }
    found
}

fn compiled(name: &str) -> glazec::Compiled {
    let path = format!("{}/../../../materials/{name}.ron", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    match glazec::compile_source(Some(&format!("{name}.ron")), &text) {
        Ok(c) => c,
        Err(e) => panic!("{name}: {e:?}"),
    }
}

/// The material's parameter values: its defaults, with `overrides` by name.
fn values(c: &glazec::Compiled, overrides: &[(&str, glazec::model::ParamValue)]) -> Vec<glazec::model::ParamValue> {
    c.material
        .params
        .iter()
        .map(|p| overrides.iter().find(|(n, _)| *n == p.name).map_or(p.default, |(_, v)| *v))
        .collect()
}

/// A local frame with n = +z: the coordinates of `d` in it (glazec's CPU evaluation has its own
/// glam version; vectors cross over as components).
fn local(n: Vec3, d: Vec3) -> glazec_glam::Vec3 {
    let t = n.any_orthonormal_vector();
    let b = n.cross(t);
    glazec_glam::Vec3::new(d.dot(t), d.dot(b), d.dot(n))
}

struct Scene {
    headless: Headless,
    camera: Entity,
    light: Entity,
    glaze: Handle<TunableGlaze>,
    floor: Entity,
}

fn scene() -> Scene {
    let mut headless = Headless::new(WIDTH, HEIGHT);
    let target = headless.target.clone();
    let world = headless.app.world_mut();
    world.insert_resource(GlobalAmbientLight::NONE);
    let sphere = world.resource_mut::<Assets<Mesh>>().add(Sphere::new(1.0).mesh().uv(128, 64));
    let floor = world.resource_mut::<Assets<Mesh>>().add(Plane3d::default().mesh().size(12.0, 12.0));
    let glaze = world.resource_mut::<Assets<TunableGlaze>>().add(TunableGlaze::default());
    let gold = world.resource_mut::<Assets<CoatedGold>>().add(CoatedGold::default());
    let clay = world.resource_mut::<Assets<Clay>>().add(Clay::default());
    world.spawn((Mesh3d(sphere.clone()), MeshMaterial3d(glaze.clone()), Transform::from_xyz(SPHERE_X[0], 0.0, 0.0)));
    world.spawn((Mesh3d(sphere), MeshMaterial3d(gold), Transform::from_xyz(SPHERE_X[1], 0.0, 0.0)));
    let floor = world.spawn((Mesh3d(floor), MeshMaterial3d(clay), Transform::from_xyz(0.0, -1.0, 0.0))).id();
    let light = world
        .spawn((
            DirectionalLight { illuminance: ILLUMINANCE, shadow_maps_enabled: false, ..default() },
            // Light arrives from +x and above: the left sphere's shadow falls on the floor to its left.
            Transform::default().looking_to(-light_direction(), Vec3::Y),
        ))
        .id();
    let camera = world
        .spawn((
            Camera3d::default(),
            Camera { clear_color: ClearColorConfig::Custom(Color::BLACK), ..default() },
            bevy::camera::RenderTarget::Image(target.into()),
            Projection::Perspective(PerspectiveProjection::default()),
            Msaa::Off,
            Tonemapping::None,
            DebandDither::Disabled,
            Exposure::default(),
            Transform::from_xyz(0.0, 1.5, 7.0).looking_at(Vec3::new(0.0, -0.3, 0.0), Vec3::Y),
        ))
        .id();
    Scene { headless, camera, light, glaze, floor }
}

/// Unit vector towards the directional light.
fn light_direction() -> Vec3 {
    Vec3::new(1.0, 0.6, 0.35).normalize()
}

/// The camera's ray through pixel (x, y)'s centre, and the exposure.
fn camera_ray(world: &mut World, camera: Entity, x: u32, y: u32) -> Option<Ray3d> {
    let mut query = world.query::<(&Camera, &GlobalTransform)>();
    let (cam, transform) = query.get(world, camera).ok()?;
    cam.viewport_to_world(transform, Vec2::new(x as f32 + 0.5, y as f32 + 0.5)).ok()
}

fn world_to_pixel(world: &mut World, camera: Entity, p: Vec3) -> Option<Vec2> {
    let mut query = world.query::<(&Camera, &GlobalTransform)>();
    let (cam, transform) = query.get(world, camera).ok()?;
    cam.world_to_viewport(transform, p).ok()
}

/// Where the ray first meets the unit sphere at `center`.
fn hit_sphere(ray: Ray3d, center: Vec3) -> Option<Vec3> {
    let oc = ray.origin - center;
    let d = *ray.direction;
    let b = oc.dot(d);
    let disc = b * b - (oc.dot(oc) - 1.0);
    (disc > 0.0).then(|| ray.origin + d * (-b - disc.sqrt()))
}

/// Compares every qualifying pixel of the sphere at `center` with `expected(n, v, l)`; returns the
/// number of pixels compared and the worst relative error.
fn compare_sphere(
    scene: &mut Scene,
    image: &Image,
    center: Vec3,
    expected: &dyn Fn(Vec3, Vec3, Vec3) -> Vec3,
) -> (usize, f32) {
    let directional = |_: Vec3| (light_direction(), ILLUMINANCE);
    compare_lit(scene, image, center, &directional, expected)
}

/// [`compare_sphere`] under any light: `light(p)` gives the unit direction towards it from the
/// surface point `p` and the illuminance it brings there (on a surface facing it).
fn compare_lit(
    scene: &mut Scene,
    image: &Image,
    center: Vec3,
    light: &dyn Fn(Vec3) -> (Vec3, f32),
    expected: &dyn Fn(Vec3, Vec3, Vec3) -> Vec3,
) -> (usize, f32) {
    compare_pixels(scene, image, center, &|p, n, v| {
        let (l, illuminance) = light(p);
        (n.dot(l) >= MIN_COSINE).then(|| expected(n, v, l) * illuminance)
    })
}

/// Compares the sphere at `center`'s pixels (where n·v ≥ MIN_COSINE) with `radiance(p, n, v)`
/// × the camera's exposure, where it gives a value (`None`: not compared) inside [DARKEST,
/// BRIGHTEST]; returns the number of pixels compared and the worst relative error.
fn compare_pixels(
    scene: &mut Scene,
    image: &Image,
    center: Vec3,
    radiance: &dyn Fn(Vec3, Vec3, Vec3) -> Option<Vec3>,
) -> (usize, f32) {
    let exposure = Exposure::default().exposure();
    let (mut count, mut worst) = (0, 0.0_f32);
    for y in 0..HEIGHT {
        for x in 0..WIDTH {
            let Some(ray) = camera_ray(scene.headless.app.world_mut(), scene.camera, x, y) else { continue };
            let Some(p) = hit_sphere(ray, center) else { continue };
            let n = (p - center).normalize();
            let v = -*ray.direction;
            if n.dot(v) < MIN_COSINE {
                continue;
            }
            let Some(want) = radiance(p, n, v).map(|r| r * exposure) else { continue };
            if want.min_element() < DARKEST || want.max_element() > BRIGHTEST {
                continue;
            }
            let got = pixel(image, x, y);
            worst = worst.max(((got - want).abs() / want).max_element());
            count += 1;
        }
    }
    (count, worst)
}

/// Writes a capture to `$GLAZEC_BEVY_IMAGES/<name>.png` when that is set (to look at a failure).
fn keep(image: &Image, name: &str) {
    if let Some(dir) = std::env::var_os("GLAZEC_BEVY_IMAGES") {
        let path = std::path::Path::new(&dir).join(format!("{name}.png"));
        if let Err(e) = glazec_bevy_scene::save_png(image, &path) {
            eprintln!("cannot write {}: {e}", path.display());
        }
    }
}

fn cpu_eval(c: &glazec::Compiled, values: &[glazec::model::ParamValue]) -> impl Fn(Vec3, Vec3, Vec3) -> Vec3 {
    move |n: Vec3, v: Vec3, l: Vec3| {
        let f = glazec::eval::brdf(&c.material, values, local(n, l), local(n, v));
        Vec3::new(f.x, f.y, f.z) * n.dot(l).max(0.0)
    }
}

#[test]
fn bevy_lights_glazec_materials_as_the_cpu_evaluates_them() {
    if !adapter_or_skip() {
        return;
    }
    use glazec::model::ParamValue;
    let glaze_cpu = compiled("tunable_glaze");
    let gold_cpu = compiled("coated_gold");
    let mut s = scene();
    let left = Vec3::new(SPHERE_X[0], 0.0, 0.0);
    let right = Vec3::new(SPHERE_X[1], 0.0, 0.0);

    // 1. The defaults, no shadows.
    let first = s.headless.capture_settled();
    keep(&first, "1-defaults");
    let defaults = values(&glaze_cpu, &[]);
    let (count, worst) = compare_sphere(&mut s, &first, left, &cpu_eval(&glaze_cpu, &defaults));
    println!("tunable_glaze (defaults): {count} pixels, worst relative error {worst:.4}");
    assert!(count >= MIN_PIXELS && worst <= RELATIVE_TOLERANCE, "tunable_glaze: {count} pixels, worst {worst}");
    let gold_values = values(&gold_cpu, &[]);
    let (count, worst) = compare_sphere(&mut s, &first, right, &cpu_eval(&gold_cpu, &gold_values));
    println!("coated_gold: {count} pixels, worst relative error {worst:.4}");
    assert!(count >= MIN_PIXELS / 4 && worst <= RELATIVE_TOLERANCE, "coated_gold: {count} pixels, worst {worst}");

    // 2. A parameter changed on the Bevy material: the very next frame shows it.
    {
        let world = s.headless.app.world_mut();
        let mut glazes = world.resource_mut::<Assets<TunableGlaze>>();
        let mut glaze = glazes.get_mut(&s.glaze).expect("the glaze is alive");
        glaze.glaze_roughness = 0.45;
        glaze.body_albedo = Vec3::new(0.55, 0.85, 0.45);
    }
    let second = s.headless.capture();
    keep(&second, "2-changed");
    let changed = values(
        &glaze_cpu,
        &[("glaze_roughness", ParamValue::Scalar(0.45)), ("body_albedo", ParamValue::Rgb([0.55, 0.85, 0.45]))],
    );
    let (count, worst) = compare_sphere(&mut s, &second, left, &cpu_eval(&glaze_cpu, &changed));
    println!("tunable_glaze (changed): {count} pixels, worst relative error {worst:.4}");
    assert!(count >= MIN_PIXELS && worst <= RELATIVE_TOLERANCE, "changed glaze: {count} pixels, worst {worst}");

    // 3. Shadows: the floor where the left sphere's shadow falls, without and with shadow maps.
    let l = light_direction();
    let shadow_point = left - l * ((1.0 + left.y) / l.y);
    let floor_pixel = world_to_pixel(s.headless.app.world_mut(), s.camera, shadow_point).expect("on screen");
    let (fx, fy) = (floor_pixel.x as u32, floor_pixel.y as u32);
    // A floor point in front of the spheres, where no shadow falls: the floor is still drawn.
    let open =
        world_to_pixel(s.headless.app.world_mut(), s.camera, Vec3::new(shadow_point.x, -1.0, 2.0)).expect("on screen");
    let (ox, oy) = (open.x as u32, open.y as u32);
    let unshadowed = pixel(&second, fx, fy);
    s.headless.app.world_mut().get_mut::<DirectionalLight>(s.light).expect("the light").shadow_maps_enabled = true;
    let third = s.headless.capture_settled();
    keep(&third, "3-shadows");
    let shadowed = pixel(&third, fx, fy);
    println!("floor at ({fx}, {fy}): {unshadowed} unshadowed, {shadowed} shadowed");
    assert!(unshadowed.max_element() > FLOOR_LIT, "the floor is lit: {unshadowed}");
    assert!(shadowed.max_element() <= SHADOWED_AT_MOST * unshadowed.max_element(), "{shadowed} vs {unshadowed}");
    let (before, after) = (pixel(&second, ox, oy), pixel(&third, ox, oy));
    println!("floor at ({ox}, {oy}), out of the shadow: {before} without shadow maps, {after} with");
    assert!(
        before.max_element() > FLOOR_LIT
            && (after - before).abs().max_element() <= RELATIVE_TOLERANCE * before.max_element(),
        "{after} vs {before}"
    );
    // `NotShadowReceiver` on the floor: its shadowed point is lit again.
    s.headless.app.world_mut().entity_mut(s.floor).insert(bevy::light::NotShadowReceiver);
    let receiver_off = s.headless.capture_settled();
    let relit = pixel(&receiver_off, fx, fy);
    println!("floor at ({fx}, {fy}) with NotShadowReceiver: {relit}");
    assert!(
        (relit - unshadowed).abs().max_element() <= RELATIVE_TOLERANCE * unshadowed.max_element(),
        "{relit} vs {unshadowed}"
    );
    s.headless.app.world_mut().entity_mut(s.floor).remove::<bevy::light::NotShadowReceiver>();

    // 4. A uniform environment map alone: the directional albedo × its radiance.
    let world = s.headless.app.world_mut();
    world.get_mut::<DirectionalLight>(s.light).expect("the light").illuminance = 0.0;
    const ENVIRONMENT: f32 = 500.0;
    let environment = EnvironmentMapLight {
        intensity: ENVIRONMENT,
        ..EnvironmentMapLight::solid_color(&mut world.resource_mut::<Assets<Image>>(), Color::WHITE)
    };
    world.entity_mut(s.camera).insert(environment);
    let fourth = s.headless.capture_settled();
    keep(&fourth, "4-environment");
    let albedo = |_: Vec3, n: Vec3, v: Vec3| {
        let lobes = glazec::eval::environment_lobes(&gold_cpu.material, &gold_values, local(n, n), local(n, v));
        let albedo: glazec_glam::Vec3 = lobes.iter().map(|l| l.weight).sum();
        Some(Vec3::new(albedo.x, albedo.y, albedo.z) * ENVIRONMENT)
    };
    let (count, worst) = compare_pixels(&mut s, &fourth, right, &albedo);
    println!("coated_gold under a uniform environment: {count} pixels, worst relative error {worst:.4}");
    assert!(count >= MIN_PIXELS / 4 && worst <= RELATIVE_TOLERANCE, "environment: {count} pixels, worst {worst}");

    // 5. A point light alone (clustered): inverse-square falloff with Bevy's range cut-off.
    let world = s.headless.app.world_mut();
    world.entity_mut(s.camera).remove::<EnvironmentMapLight>();
    let position = Vec3::new(-0.2, 1.6, 2.4);
    let point_light = world
        .spawn((
            PointLight { intensity: POINT_LUMENS, range: POINT_RANGE, ..default() },
            Transform::from_translation(position),
        ))
        .id();
    let fifth = s.headless.capture_settled();
    keep(&fifth, "5-point");
    let point = |p: Vec3| {
        let to_light = position - p;
        let d2 = to_light.length_squared();
        let cut = (1.0 - (d2 / (POINT_RANGE * POINT_RANGE)).powi(2)).clamp(0.0, 1.0);
        (to_light.normalize(), POINT_LUMENS / (4.0 * std::f32::consts::PI) * cut * cut / d2)
    };
    let (count, worst) = compare_lit(&mut s, &fifth, left, &point, &cpu_eval(&glaze_cpu, &changed));
    println!("tunable_glaze under a point light: {count} pixels, worst relative error {worst:.4}");
    assert!(count >= MIN_PIXELS && worst <= RELATIVE_TOLERANCE, "point light: {count} pixels, worst {worst}");

    // 6. A spot light alone, its cone's edge across the sphere: Bevy's smooth cone
    //    saturate((cos θ − cos outer) / (cos inner − cos outer))² on top of the point light's falloff.
    let world = s.headless.app.world_mut();
    world.despawn(point_light);
    let spot = Transform::from_translation(position).looking_at(left, Vec3::Y);
    let (inner, outer) = SPOT_ANGLES;
    world.spawn((
        SpotLight { intensity: POINT_LUMENS, range: POINT_RANGE, inner_angle: inner, outer_angle: outer, ..default() },
        spot,
    ));
    let sixth = s.headless.capture_settled();
    keep(&sixth, "6-spot");
    let axis = *spot.forward();
    let cone = |p: Vec3| {
        let (l, illuminance) = point(p);
        let edge = ((-l).dot(axis) - outer.cos()) / (inner.cos() - outer.cos());
        (l, illuminance * edge.clamp(0.0, 1.0).powi(2))
    };
    let (count, worst) = compare_lit(&mut s, &sixth, left, &cone, &cpu_eval(&glaze_cpu, &changed));
    println!("tunable_glaze under a spot light: {count} pixels, worst relative error {worst:.4}");
    assert!(count >= MIN_PIXELS / 2 && worst <= RELATIVE_TOLERANCE, "spot light: {count} pixels, worst {worst}");
}
