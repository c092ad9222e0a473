//! The opaque body at the bottom of a stack: its BRDF at its level's directions and the albedos
//! the coats above it need.

use super::geometry::{Geometry, level_name};
use super::inputs::{Body, Inputs};
use super::level::Albedo;
use crate::math::tables::{self, TableId};
use crate::math::terms::*;
use crate::math::{Named, Real, Vector};
use crate::model::ConductorFresnel;

/// The base's own BRDF at the directions of its level. `n_medium` is the absolute IOR of the
/// medium the base sits in (`None`: air), which changes a conductor's Fresnel reflectance;
/// `blur` widens a conductor's lobe (see [`interfaced`]).
pub(super) fn base_brdf<F: Real>(
    body: &Body<'_>,
    inputs: &Inputs<F>,
    g: &Geometry<F>,
    n_medium: Option<F>,
    blur: Option<F>,
) -> F::Vec {
    let f = unguarded_base_brdf(body, inputs, g, n_medium, blur);
    match g.shading_cosine_ratio() {
        Some(ratio) => {
            let above = g.raw_n_dot_v.gt_lit(0.0);
            F::Vec::select(above, f * ratio, inputs.zero())
        }
        None => f,
    }
}

fn unguarded_base_brdf<F: Real>(
    body: &Body<'_>,
    inputs: &Inputs<F>,
    g: &Geometry<F>,
    n_medium: Option<F>,
    blur: Option<F>,
) -> F::Vec {
    match body {
        Body::Lambert(albedo) => fd_lambert::<F>(inputs.color(*albedo)),
        Body::OrenNayar(albedo, sigma) => {
            fd_oren_nayar(inputs.color(*albedo), inputs.scalar(*sigma), g.n_dot_v, g.n_dot_l, g.v_dot_l())
        }
        Body::Eon(albedo, r) => fd_eon(inputs.color(*albedo), inputs.scalar(*r), g.n_dot_v, g.n_dot_l, g.v_dot_l()),
        Body::Conductor(roughness, fresnel) => {
            let alpha = conductor_alpha(inputs.scalar(*roughness), blur, g.level);
            let name = |base| level_name(base, g.level);
            let half = g.half();
            let distribution = d_ggx(half.n_dot_h, half.sin2_h, alpha).named(&name("d"));
            let shadowing = g_smith_ggx_correlated(g.n_dot_v, g.n_dot_l, alpha).named(&name("g"));
            let f = conductor_fresnel(fresnel, inputs, half.v_dot_h, n_medium).named(&name("fresnel"));
            f_cook_torrance(distribution, shadowing, f, g.n_dot_v, g.n_dot_l)
        }
    }
}

/// A conductor's GGX α = r², widened to α + blur under rough coats.
pub(super) fn conductor_alpha<F: Real>(roughness: F, blur: Option<F>, level: usize) -> F {
    let alpha = roughness * roughness;
    match blur {
        Some(b) => (alpha + b).named(&level_name("alpha", level)),
        None => alpha,
    }
}

/// The body's directional albedos towards l and v and its mean albedo, for the coat above;
/// an Oren–Nayar body's at the cosines `incidence` where given (see `Depth::incidence`).
pub(super) fn body_albedo<F: Real>(
    body: &Body<'_>,
    inputs: &Inputs<F>,
    g: &Geometry<F>,
    n_medium: Option<F>,
    blur: Option<F>,
    incidence: Option<(F, F)>,
) -> Albedo<F> {
    let name = |base| level_name(base, g.level);
    let mean = base_mean_albedo(body, inputs, g.level, n_medium, blur).named(&name("rho"));
    let (e_l, e_v) = match body {
        // Lambert's albedo is the same in every direction.
        Body::Lambert(_) => (mean, mean),
        // The qualitative Oren–Nayar lobe's albedo grows towards grazing incidence (its B term):
        // its mean at every direction stated `wet_clay`'s albedo 8% too high at normal incidence
        // (docs/accuracy.md, "The stated albedo against the reference"). A rough coat above
        // spreads the light it lets in, and at Snell's cosines `disney_clay` under a GTR1 coat
        // came out 3% dark at 50°–60° (body p90 1.8% → 2.1%); at the coat's path cosines 1.6%.
        Body::OrenNayar(albedo, sigma) => {
            let (albedo, sigma) = (inputs.color(*albedo), inputs.scalar(*sigma));
            let (mu_l, mu_v) = incidence.unwrap_or((g.n_dot_l, g.n_dot_v));
            (albedo_oren_nayar(albedo, sigma, mu_l), albedo_oren_nayar(albedo, sigma, mu_v))
        }
        Body::Eon(albedo, r) => {
            let (albedo, r) = (inputs.color(*albedo), inputs.scalar(*r));
            (albedo_eon(albedo, r, g.n_dot_l), albedo_eon(albedo, r, g.n_dot_v))
        }
        // E(μ) ≈ E_GGX(μ; α) F(μ): the white lobe's albedo times Fresnel at the mirror direction.
        Body::Conductor(roughness, fresnel) => {
            let r = conductor_alpha(inputs.scalar(*roughness), blur, g.level).sqrt();
            let at = |mu: F| {
                let white = tables::lookup(TableId::GgxAlbedo, &[mu, r]);
                conductor_fresnel(fresnel, inputs, mu, n_medium) * white
            };
            (at(g.n_dot_l), at(g.n_dot_v))
        }
    };
    // The light's first hit on a normal-mapped body scales with its own cosine (see
    // `Geometry::shading_cosine_ratio`), and so does all that follows from it.
    let e_l = match g.shading_cosine_ratio() {
        Some(ratio) => e_l * ratio,
        None => e_l,
    };
    Albedo { e_l: e_l.named(&name("albedo_l")), e_v: e_v.named(&name("albedo_v")), mean, split: None }
}

pub(super) fn conductor_fresnel<F: Real>(
    fresnel: &ConductorFresnel,
    inputs: &Inputs<F>,
    cos: F,
    n_medium: Option<F>,
) -> F::Vec {
    match fresnel {
        ConductorFresnel::F0(f0) => {
            let f0 = inputs.color(*f0);
            let f0 = n_medium.map_or(f0, |n| f0_under_medium(f0, n).named("f0_under_coat"));
            f_schlick(f0, cos)
        }
        ConductorFresnel::Complex { eta, k } => {
            let (eta, k) = (inputs.color(*eta), inputs.color(*k));
            let (eta, k) = match n_medium {
                Some(n) => (eta / n, k / n),
                None => (eta, k),
            };
            fr_conductor(cos, eta, k)
        }
    }
}

/// The hemispherical-average albedo of the base (for the interfaced method's inter-reflections).
fn base_mean_albedo<F: Real>(
    body: &Body<'_>,
    inputs: &Inputs<F>,
    level: usize,
    n_medium: Option<F>,
    blur: Option<F>,
) -> F::Vec {
    match body {
        Body::Lambert(albedo) => inputs.color(*albedo),
        Body::OrenNayar(albedo, sigma) => albedo_avg_oren_nayar(inputs.color(*albedo), inputs.scalar(*sigma)),
        Body::Eon(albedo, r) => albedo_avg_eon(inputs.color(*albedo), inputs.scalar(*r)),
        Body::Conductor(roughness, fresnel) => {
            let f0 = conductor_fresnel(fresnel, inputs, inputs.lit(1.0), n_medium);
            let r = conductor_alpha(inputs.scalar(*roughness), blur, level).sqrt();
            let white = tables::lookup(TableId::GgxAlbedoAvg, &[r]);
            albedo_avg_conductor::<F>(f0) * white
        }
    }
}
