//! What the interfaced method hands up from one level to the coat above it: the level's BRDF
//! and albedos ([`Level`], [`Albedo`]), and the blur rough coats add to the lobes under them.

use super::geometry::level_name;
use crate::math::Real;

/// What the interfaced method knows about the layer under a coat, at that layer's directions.
pub(super) struct Level<F: Real> {
    /// f at the level's (refracted) directions.
    pub(super) f: F::Vec,
    /// Its directional and mean albedos, when the coat above needs them.
    pub(super) albedo: Option<Albedo<F>>,
    /// A bare conductor: its reflection stays a lobe (see `interfaced_glossy_under`).
    pub(super) glossy: bool,
    /// The GGX α of that lobe (a conductor, and the levels over one).
    pub(super) alpha: Option<F>,
    /// How much more easily than diffuse light the light this level sends up escapes the coats
    /// above it (see [`first_pass`]); 1 for the body.
    pub(super) boost: F,
    /// Its top coat's transmission T(μ) towards l and v (`None` for the body).
    pub(super) transmission: Option<(F, F)>,
}

/// Directional albedos towards l and v, and the hemispherical mean.
#[derive(Clone, Copy)]
pub(super) struct Albedo<F: Real> {
    pub(super) e_l: F::Vec,
    pub(super) e_v: F::Vec,
    pub(super) mean: F::Vec,
    /// Over a conductor: where the light of `e_l` and `e_v` goes (`None` for a diffusing layer).
    pub(super) split: Option<(Split<F>, Split<F>)>,
}

/// Where the light a coated conductor reflects towards one side goes, at the directions under
/// the coat above it, which lets out of each part only what its escape cone holds
/// (`trapped::trapped_shares`). The parts add up to the side's directional albedo.
#[derive(Clone, Copy)]
pub(super) struct Split<F: Real> {
    /// The level's top coat's own reflection, 1 − T(μ): a mirror's (`alpha` `None`; a GTR1
    /// lobe's too) or a GGX lobe of α `alpha` about the mirror direction.
    pub(super) specular: F,
    pub(super) alpha: Option<F>,
    /// What leaves near the mirror direction as the conductor's lobe (GGX α the level's
    /// [`Level::alpha`]).
    pub(super) lobe: F::Vec,
    /// The rest, spread over the hemisphere like diffuse light: the glossy level's remainder,
    /// and what a coat above has trapped and let out.
    pub(super) spread: F::Vec,
}

/// How much a rough coat widens a lobe under it (a conductor's, or a coat's own reflection seen
/// through it): α += BLUR_WIDTH · |1 − 1/η| m, m the median slope of the coat's microfacet
/// normals. A facet tilted by θm refracts a ray by about (1 − 1/η) θm (Walter et al. 2007, the
/// refraction Jacobian at normal incidence). The light crosses the coat twice, through
/// independent facets, so the two deviations add in quadrature: √2 (1 − 1/η) m in direction. A
/// GGX lobe of width α in half-vector slope reflects into 2α in direction, so that spread is
/// (1/√2)(1 − 1/η) m in the lower lobe's α. GGX slopes are heavy-tailed, so the added width adds
/// to the lower lobe's own linearly rather than in quadrature (Belcour 2018 adds variances).
/// The median slope is GGX's α (its sampling gives tan²θm = α² u/(1 − u), Walter et al. 2007)
/// and GTR1's √α (tan²θm = (α^(2(1−u)) − α²)/(1 − α^(2(1−u))), Burley 2012, at u = ½), so a
/// GTR1 coat of roughness r blurs like a GGX coat of α = r: its long tails spread what is seen
/// through it far more than its α says. Against the reference (standard set, copper under
/// coats of roughness 0.5) this gives a lobe error of 9–14%.
pub(super) const BLUR_WIDTH: f32 = std::f32::consts::FRAC_1_SQRT_2;

/// The blur of the rough coats above a level (see [`BLUR_WIDTH`]), kept by the kind of their
/// microfacet distribution, because the two compose differently with a lobe seen through them;
/// each as it is along the normal (what a conductor's lobe takes) and at the light's and the
/// view's directions (what a coat's lobe takes, [`coat_blur`]).
#[derive(Clone, Copy)]
pub(super) struct Blur<F: Real> {
    /// The sum of the GGX coats' blurs along the normal.
    pub(super) ggx: Option<F>,
    /// The sum of the GTR1 coats' blurs along the normal.
    pub(super) gtr1: Option<F>,
    /// The GGX coats' blurs at (l, v).
    pub(super) ggx_dir: Option<(F, F)>,
    /// The GTR1 coats' blurs at (l, v).
    pub(super) gtr1_dir: Option<(F, F)>,
}

impl<F: Real> Blur<F> {
    /// No rough coat above.
    pub(super) fn none() -> Self {
        Blur { ggx: None, gtr1: None, ggx_dir: None, gtr1_dir: None }
    }

    /// The whole blur, added to a conductor's α (what `BLUR_WIDTH` was measured with).
    pub(super) fn total(self) -> Option<F> {
        match (self.ggx, self.gtr1) {
            (Some(g), Some(t)) => Some(g + t),
            (g, t) => g.or(t),
        }
    }

    /// The median slope `m` of a coat's lobe (GGX's α, GTR1's √α) seen through the coats
    /// above: √(m² + m·g + g²) + t, g the GGX blur and t the GTR1 blur. Two GGX slope
    /// distributions convolve into one whose peak is that of a GGX of about √(m² + mg + g²)
    /// (within 2% for g/m from 0.03 to 3.5, by numerical integration; docs/derivations.md, "A
    /// lobe seen through a rough coat"), narrower than m + g: with m + g the four-GGX-coat stack
    /// of the multi-coat set was 1.1% off in the body (p90) against 0.6%. GTR1's long tails carry
    /// most of what it spreads far from the peak, and matching the peak leaves them out (the
    /// `Gtr1` stack over Plastic: 7.2% against 3.9% with the linear sum), so its blur adds
    /// linearly. Per direction, (towards l, towards v); `None` without a rough coat above.
    pub(super) fn widen(self, m: F, name: &str) -> Option<(F, F)> {
        if self.ggx_dir.is_none() && self.gtr1_dir.is_none() {
            return None;
        }
        let one = |g: Option<F>, t: Option<F>| {
            let through_ggx = match g {
                Some(g) => (m.sq() + m * g + g.sq()).sqrt(),
                None => m,
            };
            t.map_or(through_ggx, |t| through_ggx + t)
        };
        let widened_l = one(self.ggx_dir.map(|d| d.0), self.gtr1_dir.map(|d| d.0));
        let widened_v = one(self.ggx_dir.map(|d| d.1), self.gtr1_dir.map(|d| d.1));
        // Named where it is computed at run time (a literal α stays inline).
        let named = |w: F, side: &str| if w.known().is_some() { w } else { w.named(&format!("{name}_{side}")) };
        Some((named(widened_l, "l"), named(widened_v, "v")))
    }
}

/// The blur a rough coat adds to the `blur` of the coats above it (see [`BLUR_WIDTH`]), from the
/// median slope of its microfacet normals (`median_slope`: α for GGX, √α for GTR1, whose blur
/// is kept apart when `gtr1`) and its relative IOR `eta`; a smooth coat adds none.
///
/// At a direction of cosine μ above the coat and μ′ under it, a facet tilted by a slope s moves
/// the refracted ray's horizontal part by (μ′ − μ/η) s (to first order: the ray refracted about
/// n + s is d/η + (μ/η − μ′)(n + s), Walter et al. 2007, eq. 40), isotropically about the ray;
/// the half vector of a reflection under the coat moves by that over 2μ′ in slope. The blur at
/// that direction is therefore |1 − μ/(η μ′)| m BLUR_WIDTH (`cosines`: (μ, μ′) towards l and
/// towards v; `None` where no rough coat lies below to take it), |1 − 1/η| m BLUR_WIDTH along
/// the normal. At 55° under an η 1.5 coat it is 1.6
/// times that along the normal, at 75° 2.3 times: with the blur along the normal a `Ggx(0.25)`
/// coat's peak seen through a `Gtr1(0.15)` coat was 1.40× the reference at 55° and 2.04× at 75°
/// (1.04× at 5°), and 1.29× and 1.41× through a `Ggx(0.3)` coat; with the blur at the
/// directions it is 0.90× and 0.88×, and 0.98× and 0.79× (`glazec eval` against the reference,
/// 262,144 walks). A conductor's lobe keeps the blur along the normal, what its glossy tables
/// and the blur's width were fitted with: at the directions, the gold stack of the multi-coat
/// set left its targets (body p90 6.4% → 7.6%, grazing 25.5%) and the GTR1 stack over copper
/// its body target (7.0% → 11.4%).
pub(super) fn coat_blur<F: Real>(
    median_slope: Option<F>,
    gtr1: bool,
    eta: F,
    blur: Blur<F>,
    k: usize,
    cosines: Option<((F, F), (F, F))>,
) -> Blur<F> {
    let Some(slope) = median_slope else { return blur };
    // |1 − 1/η|: a coat optically thinner than the medium above (η < 1) spreads rays too (and a
    // negative width would make α negative).
    let spread = eta.recip().one_minus().abs();
    let added = (spread * slope * BLUR_WIDTH).named(&level_name("blur", k));
    let add = |sum: Option<F>| Some(sum.map_or(added, |b| b + added));
    // At the directions only where a coat's lobe below asks for it (`cosines`).
    let add_dir = |sum: Option<(F, F)>| {
        let ((mu_l, below_l), (mu_v, below_v)) = cosines?;
        let at = |mu: F, below: F, side: &str| {
            let spread = (mu / (eta * below.at_least(BLUR_COSINE_MIN))).one_minus().abs();
            (spread * slope * BLUR_WIDTH).named(&level_name(&format!("blur_{side}"), k))
        };
        let (l, v) = (at(mu_l, below_l, "l"), at(mu_v, below_v, "v"));
        Some(sum.map_or((l, v), |b| (b.0 + l, b.1 + v)))
    };
    if gtr1 {
        Blur { gtr1: add(blur.gtr1), gtr1_dir: add_dir(blur.gtr1_dir), ..blur }
    } else {
        Blur { ggx: add(blur.ggx), ggx_dir: add_dir(blur.ggx_dir), ..blur }
    }
}

/// Smallest refracted cosine μ′ the blur at a direction divides by ([`coat_blur`]): under total
/// internal reflection (η < 1) μ′ is 0.
const BLUR_COSINE_MIN: f32 = 0.05;
