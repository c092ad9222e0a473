//! Light a glossy body sends outside a coat's escape cone: total internal reflection traps it
//! between body and coat until the body scatters it back into the cone. Used where a glossy
//! body is not directly under its coat's glossy level (`interfaced`).

use super::geometry::{Geometry, level_name};
use super::inputs::Inputs;
use super::interface::CoatInterface;
use super::level::Albedo;
use crate::math::tables::{self, TableId};
use crate::math::terms::*;
use crate::math::{Named, Real, Vector};

/// What a glossy body under a coat sends outside the coat's escape cone, at the directions
/// `below` (under the coat): the trapped shares of its reflections towards l and v, and what
/// becomes of trapped light.
#[derive(Clone, Copy)]
pub(super) struct Trapped<F: Real> {
    /// μc, the escape cone's cosine inside (0 without total internal reflection).
    pub(super) mu_c: F,
    pub(super) p_l: F,
    pub(super) p_v: F,
    /// The slab's round trip for trapped light, R(τ)/R(0).
    pub(super) round_trip: F::Vec,
    /// q, the share of trapped light the body sends into the cone at each bounce.
    pub(super) q: F,
}

/// The trapped shares of the glossy body of GGX α under `interface` (see [`Trapped`]);
/// `r_clear` is the clear slab's return R(0).
pub(super) fn trapped_shares<F: Real>(
    interface: &CoatInterface<'_, F>,
    below: &Geometry<F>,
    alpha: F,
    (r_return, r_clear): (F::Vec, F::Vec),
    inputs: &Inputs<F>,
) -> Trapped<F> {
    let name = |base: &str| level_name(base, below.level);
    let mu_c = escape_cone_cosine(interface.eta).named(&name("mu_c"));
    let p_l = trapped_share(below.n_dot_l, mu_c, alpha).named(&name("trapped_l"));
    let p_v = trapped_share(below.n_dot_v, mu_c, alpha).named(&name("trapped_v"));
    // The round trip of trapped light: R(τ)/R(0), the absorption of the slab's diffuse return.
    let round_trip = r_return / r_clear.max(inputs.lit(1e-4).splat());
    let q = trapped_escape(mu_c, alpha).named(&name("trapped_escape"));
    Trapped { mu_c, p_l, p_v, round_trip, q }
}

/// The light a glossy body of GGX α under a coat sends outside the escape cone (`trapped_lobe`,
/// from its `shares`, [`trapped_shares`]), spread over the azimuth about the forward direction
/// like the glossy level's own remainder (`forward_azimuth_weight`, κ from `glossy_spread` at
/// the body's α and the coat's roughness and IOR: total internal reflection and a glossy
/// reflection both keep the light going on) and tilted per channel like it
/// (`forward_azimuth_tilt`); `above` the directions above the coat.
pub(super) fn trapped<F: Real>(
    interface: &CoatInterface<'_, F>,
    above: &Geometry<F>,
    below: &Geometry<F>,
    albedo: &Albedo<F>,
    alpha: F,
    shares: &Trapped<F>,
    inputs: &Inputs<F>,
) -> F::Vec {
    let name = |base: &str| level_name(base, below.level);
    let eta = interface.eta;
    let Trapped { mu_c, p_l, p_v, round_trip, q } = *shares;
    let lobe = trapped_lobe(albedo.e_l, p_l, albedo.e_v, p_v, mu_c, round_trip, albedo.mean, q);
    let roughness = interface.roughness.unwrap_or(inputs.lit(0.0));
    let kappa = |mu: F| tables::lookup(TableId::GlossySpread, &[mu, alpha.sqrt(), roughness, eta]);
    let kappa = (kappa(above.raw_n_dot_l) * kappa(above.raw_n_dot_v)).at_least(0.0).sqrt();
    let sines = forward_sines::<F>(above.n, above.v, above.l).named(&name("trapped_sines"));
    let rho = (kappa * sines).min(inputs.lit(0.95));
    let weight = forward_azimuth_weight(rho, forward_cosine(above.n, above.v, above.l, sines));
    // Tilted per channel as the glossy level's remainder is (`glossy_spread_colour`), with
    // the event counts this lobe assumes: a geometric count of retention 1 − q. The light a
    // coloured body lets survive took fewer bounces and kept going forward more; leaving
    // sideways or backwards takes the most bounces.
    let none = inputs.lit(0.0);
    let rho_c = glossy_spread_colour(rho, none, none, none, q.one_minus(), albedo.mean);
    let spread = forward_azimuth_tilt(rho, rho_c, weight) * weight;
    let lobe = lobe * spread.named(&name("trapped_spread"));
    // Without total internal reflection (η ≤ 1) nothing is trapped.
    F::Vec::select(mu_c.gt_lit(0.0), lobe, inputs.zero())
}
