//! The example scene: glazec's shipped materials on spheres and the textured, normal-mapped clay
//! on a torus, on a floor of `mud_clay`, lit by Bevy's own lights — a directional light with
//! cascaded shadows, a warm point light and a cool spot light with shadows, an environment map (a
//! sky gradient) and ambient light — with fog and ACES tonemapping, rendered headless into a PNG
//! file.
//!
//! `cargo run --release -p glazec_bevy_scene -- OUT.png` (from `crates/glazec_bevy`).

use bevy::asset::RenderAssetUsages;
use bevy::core_pipeline::tonemapping::Tonemapping;
use bevy::image::{CompressedImageFormats, ImageAddressMode, ImageSampler, ImageSamplerDescriptor, ImageType};
use bevy::light::GlobalAmbientLight;
use bevy::prelude::*;
use glazec_bevy_scene::materials as m;
use glazec_bevy_scene::textured::textured_clay::TexturedClay;
use glazec_bevy_scene::{Headless, save_png};

const WIDTH: u32 = 1280;
const HEIGHT: u32 = 720;

fn main() {
    let out = std::env::args().nth(1).unwrap_or_else(|| "bevy_scene.png".to_string());
    let mut headless = Headless::new(WIDTH, HEIGHT);
    let target = headless.target.clone();
    build_scene(headless.app.world_mut(), target);
    let image = headless.capture_settled();
    if let Err(e) = save_png(&image, std::path::Path::new(&out)) {
        eprintln!("error: cannot write {out}: {e}");
        std::process::exit(1);
    }
    println!("wrote {out} ({WIDTH}×{HEIGHT})");
}

/// A PNG of `examples/textures` as an image sampled with repeat (the maps tile).
fn texture(images: &mut Assets<Image>, bytes: &[u8], srgb: bool) -> Handle<Image> {
    let sampler = ImageSampler::Descriptor(ImageSamplerDescriptor {
        address_mode_u: ImageAddressMode::Repeat,
        address_mode_v: ImageAddressMode::Repeat,
        ..ImageSamplerDescriptor::linear()
    });
    let image = Image::from_buffer(
        bytes,
        ImageType::Extension("png"),
        CompressedImageFormats::NONE,
        srgb,
        sampler,
        RenderAssetUsages::default(),
    )
    .expect("the example's maps are valid PNG files");
    images.add(image)
}

fn build_scene(world: &mut World, target: Handle<Image>) {
    world.insert_resource(GlobalAmbientLight { brightness: 40.0, ..default() });
    let (sphere, floor, torus) = {
        let mut meshes = world.resource_mut::<Assets<Mesh>>();
        let torus = Torus::new(0.45, 1.0).mesh().minor_resolution(48).major_resolution(96).build();
        let torus = torus.with_generated_tangents().expect("a torus has normals and UVs");
        (
            meshes.add(Sphere::new(0.5).mesh().uv(96, 48)),
            meshes.add(Plane3d::default().mesh().size(30.0, 30.0)),
            meshes.add(torus),
        )
    };
    // Three rows of spheres: every shipped material.
    let mut place = Vec::new();
    macro_rules! sphere {
        ($world:expr, $ty:ty) => {{
            let handle = $world.resource_mut::<Assets<$ty>>().add(<$ty>::default());
            let entity = $world.spawn((Mesh3d(sphere.clone()), MeshMaterial3d(handle))).id();
            place.push(entity);
        }};
    }
    sphere!(world, m::clay::Clay);
    sphere!(world, m::wet_clay::WetClay);
    sphere!(world, m::mud_clay::MudClay);
    sphere!(world, m::cork_clay::CorkClay);
    sphere!(world, m::paper_clay::PaperClay);
    sphere!(world, m::color_clay::ColorClay);
    sphere!(world, m::disney_clay::DisneyClay);
    sphere!(world, m::tunable_glaze::TunableGlaze);
    sphere!(world, m::red_plastic::RedPlastic);
    sphere!(world, m::lacquered_wood::LacqueredWood);
    sphere!(world, m::car_paint::CarPaint);
    sphere!(world, m::coated_gold::CoatedGold);
    sphere!(world, m::four_layer::FourLayer);
    for (i, entity) in place.iter().enumerate() {
        let (row, column) = (i / 5, i % 5);
        let x = -2.8 + 1.4 * column as f32 + if row == 1 { 0.7 } else { 0.0 };
        let z = -1.45 * row as f32;
        world.entity_mut(*entity).insert(Transform::from_xyz(x, 0.5, z + 1.0));
    }
    // The textured clay on a torus, standing at the right.
    let clay = {
        let mut images = world.resource_mut::<Assets<Image>>();
        TexturedClay {
            clay_maps: Some(texture(&mut images, include_bytes!("../../../../examples/textures/clay_maps.png"), false)),
            clay_albedo: Some(texture(
                &mut images,
                include_bytes!("../../../../examples/textures/clay_albedo.png"),
                true,
            )),
            clay_bumps: Some(texture(
                &mut images,
                include_bytes!("../../../../examples/textures/clay_bumps.png"),
                false,
            )),
            clay_pores: Some(texture(
                &mut images,
                include_bytes!("../../../../examples/textures/clay_pores.png"),
                false,
            )),
            ..default()
        }
    };
    let clay = world.resource_mut::<Assets<TexturedClay>>().add(clay);
    world.spawn((
        Mesh3d(torus),
        MeshMaterial3d(clay),
        Transform::from_xyz(4.3, 1.45, -0.6).with_rotation(Quat::from_rotation_x(1.2) * Quat::from_rotation_z(0.3)),
    ));
    let ground = world.resource_mut::<Assets<m::mud_clay::MudClay>>().add(m::mud_clay::MudClay::default());
    world.spawn((Mesh3d(floor), MeshMaterial3d(ground), Transform::default()));

    world.spawn((
        DirectionalLight { illuminance: 3500.0, shadow_maps_enabled: true, ..default() },
        Transform::default().looking_to(Vec3::new(-0.6, -0.8, -0.5), Vec3::Y),
    ));
    world.spawn((
        PointLight {
            intensity: 400_000.0,
            range: 30.0,
            shadow_maps_enabled: true,
            color: Color::srgb(1.0, 0.78, 0.55),
            ..default()
        },
        Transform::from_xyz(-3.5, 2.5, 2.5),
    ));
    world.spawn((
        SpotLight {
            intensity: 600_000.0,
            range: 30.0,
            outer_angle: 0.45,
            inner_angle: 0.3,
            shadow_maps_enabled: true,
            color: Color::srgb(0.6, 0.75, 1.0),
            ..default()
        },
        Transform::from_xyz(3.0, 4.5, 3.0).looking_at(Vec3::new(1.0, 0.5, -0.5), Vec3::Y),
    ));
    let environment = {
        let mut images = world.resource_mut::<Assets<Image>>();
        EnvironmentMapLight {
            intensity: 500.0,
            ..EnvironmentMapLight::hemispherical_gradient(
                &mut images,
                Color::srgb(0.45, 0.6, 0.95),
                Color::srgb(0.85, 0.85, 0.8),
                Color::srgb(0.25, 0.22, 0.2),
            )
        }
    };
    world.spawn((
        Camera3d::default(),
        bevy::camera::RenderTarget::Image(target.into()),
        Tonemapping::AcesFitted,
        environment,
        DistanceFog {
            color: Color::srgb(0.7, 0.75, 0.85),
            falloff: FogFalloff::Linear { start: 12.0, end: 40.0 },
            ..default()
        },
        Transform::from_xyz(0.6, 4.6, 7.8).looking_at(Vec3::new(0.6, 0.3, -0.9), Vec3::Y),
    ));
}
