//! How one coat combines with what lies under it: the seed's Weidlich–Wilkie recurrence and
//! glazec's interfaced layering (the layer's BRDF, the series of internal reflections, the
//! glossy level's lobes), and their albedos.

use std::f32::consts::PI;

use crate::math::Vector;
use crate::math::shading_fn;

use super::microfacet::TINY;

shading_fn! {
    /// Weidlich & Wilkie 2007 (Bowsher 2022, eq. 14–15): the absorption a = e^{−α l} along the path
    /// l = d (1/(n·l′) + 1/(n·v′)) through a layer of density `thickness`.
    pub fn absorption_ww(sigma_a: V, thickness: S, n_dot_l1: S, n_dot_v1: S) -> V {
        let path = thickness * (n_dot_l1.recip() + n_dot_v1.recip());
        (-(sigma_a * path)).exp()
    }
}

shading_fn! {
    /// [`absorption_ww`] for a grey layer (the same σa in every channel): one exponential
    /// instead of three.
    pub fn absorption_ww_grey(sigma_a: S, thickness: S, n_dot_l1: S, n_dot_v1: S) -> S {
        let path = thickness * (n_dot_l1.recip() + n_dot_v1.recip());
        (-(sigma_a * path)).exp()
    }
}

shading_fn! {
    /// Weidlich & Wilkie 2007 via Bowsher 2022, §3.0.3: the internal-reflection term
    /// t = (1 − G) + T21·G, with T21 = T12.
    pub fn ww_inner_reflection(g: S, t21: V) -> V {
        t21 * g + g.one_minus().splat()
    }
}

shading_fn! {
    /// Weidlich & Wilkie 2007 (Bowsher 2022, eq. 13): one step of the recurrence,
    /// f = f_r1(L, V) + T12 · f_r2(L′, V′) · a · t.
    pub fn ww_layer(f_top: V, t12: V, absorption: V, inner: V, f_below: V) -> V {
        f_top + f_below * t12 * absorption * inner
    }
}

shading_fn! {
    /// glazec's interfaced layering (docs/derivations.md, "Smooth coat over Lambert"):
    /// f_top + f_under aᵢ aₒ Tᵢ Tₒ / η², symmetric in i and o, so reciprocal.
    ///
    /// The light under a coat of relative IOR η enters with transmittance Tᵢ, is attenuated on its way
    /// down and up (aᵢ, aₒ), is reflected by what lies below (`f_under`, at refracted directions),
    /// leaves with Tₒ and is compressed by 1/η² (étendue). docs/derivations.md, "Closed-form layering
    /// models compared", sets it beside the seed's methods.
    pub fn interfaced_layer(f_top: V, t_i: S, t_o: S, a_i: V, a_o: V, f_under: V, eta: S) -> V {
        f_top + f_under * a_i * a_o * (t_i * t_o / (eta * eta))
    }
}

shading_fn! {
    /// glazec's interfaced layering, a diffusing layer below a coat (docs/derivations.md, "Smooth coat
    /// over Lambert"): f_below + Eᵢ Eₒ R / (π (1 − ρ̄ R)).
    ///
    /// The single reflection `f_below`, plus the light it reflects (directional albedos Eᵢ, Eₒ) that
    /// the coat sends back down (R, the slab's diffuse return reflectance) and that then bounces
    /// between body and coat (mean albedo ρ̄). For a Lambertian body (E = ρ̄ = ρ) the sum is
    /// ρ/(π(1 − ρR)), the exact series.
    pub fn interfaced_diffuse_under(f_below: V, e_i: V, e_o: V, rho_below: V, r_return: V) -> V {
        f_below + e_i * e_o * r_return / ((rho_below * r_return).one_minus() * PI)
    }
}

shading_fn! {
    /// glazec's interfaced layering: the albedo with which a coated layer below a coat sends back up
    /// the light the coat returns to it, ρ̄ᵣ = (ρ̄ − S)/(1 − S·again), S the share its top interface
    /// reflects (0 for a body directly under the coat). Guards: ρ̄ᵣ ≥ 0; the denominator ≥ 10⁻⁶
    /// (S → 1 under a clear slab).
    ///
    /// This is the series' ρ̄ in `interfaced_diffuse_under`, `interfaced_albedo_dir` and
    /// `interfaced_albedo`. That light arrives mostly beyond the coat's escape cone (total internal
    /// reflection), and the share S of it that the layer's top interface reflects keeps its
    /// direction: it is returned again (with the slab's return relative to a clear slab's, `again` =
    /// R(τ)/R(0)) instead of being sent up like the light the layer scatters, which may leave. A
    /// white layer under a clear coat keeps ρ̄ᵣ = 1, so no energy is lost or gained. Taking ρ̄ instead
    /// made stacks of smooth coats over Lambert 0.8 too bright against their exact answer
    /// (`glazec_lab::reference::smooth_stack`): three coats of η 1.5 by 5.6%, four by 15%; now 1.7%
    /// and 7.4%.
    pub fn returned_albedo(rho: V, s: S, again: V) -> V {
        let denominator = (again * s).one_minus().max(s.lit(1e-6).splat());
        ((rho - s.splat()) / denominator).max(s.lit(0.0).splat())
    }
}

shading_fn! {
    /// glazec's interfaced layering, a glossy body (a conductor) below a coat:
    /// f / (1 − √(Eᵢkᵢ Eₒkₒ)), kᵢ = (1 − Tᵢ) aᵢ² the coat's directional internal reflectance, Eᵢ the
    /// share of the body's albedo inside the escape cone. Guard: the denominator ≥ 10⁻⁶ (0 beyond the
    /// critical angle of a coat optically thinner than the medium above, T = 0, over a white level,
    /// where f is 0 too).
    ///
    /// Light the body reflects stays near the mirror direction, inside the coat's escape cone, so it
    /// returns with kᵢ (reciprocity of the interface) rather than the diffuse R, and the bounces keep
    /// the lobe's shape; symmetric in i and o. Eᵢ is the caller's Eᵢ(1 − pᵢ), `trapped_share`: what
    /// the body sends beyond the cone is trapped, `trapped_lobe`. With the whole albedo instead, two
    /// smooth coats (η 1.5 over η 1.02) over a white conductor of roughness 0.3 were 1.40× the
    /// reference at 75°/85° forwards and 1.58× at 89°/75°, and ∫f came to 1.015 at 85°: the light the
    /// body sends just beyond the cone's edge, where k is largest, was counted in both. Without the
    /// guard, 0/0 was NaN under three smooth coats of η 1, 0.7, 0.7 over a conductor.
    pub fn interfaced_glossy_under(f_below: V, e_i: V, k_i: V, e_o: V, k_o: V) -> V {
        f_below / (e_i * k_i * e_o * k_o).sqrt().one_minus().max(f_below.x().lit(1e-6).splat())
    }
}

shading_fn! {
    /// glazec's interfaced layering, the light a glossy body sends outside the coat's escape cone:
    /// Pᵢ Pₒ g / (π μc² (1 − ρ̄ g (1 − q))), g the slab's round-trip transmittance, q = `trapped_escape`.
    /// Guard: μc² ≥ 10⁻⁴ (without a cone nothing is trapped; the caller zeroes that case).
    ///
    /// Pᵢ, Pₒ are the shares of its albedos towards i and o beyond the cone (`trapped_shares`):
    /// trapped by total internal reflection, that light comes back with g and meets the body again,
    /// which (mean albedo ρ̄) sends a share q of it into the cone and keeps the rest trapped. By
    /// reciprocity the body sends Pₒ/(π μc²) of trapped light (projected solid angle π μc²) towards
    /// o; symmetric in i and o. Its albedo is Pᵢ g ρ̄ q/(1 − ρ̄ g (1 − q)) (taking Pₒ ≈ ρ̄ over the
    /// cone): a white body returns all trapped light.
    pub fn trapped_lobe(trapped_i: V, trapped_o: V, mu_c: S, round_trip: V, rho: V, q: S) -> V {
        trapped_i * trapped_o * round_trip / (mu_c.sq().at_least(1e-4) * PI) / (rho * round_trip * q.one_minus()).one_minus()
    }
}

shading_fn! {
    /// glazec's glossy level (a conductor under a coat): the light trapped after the first conductor
    /// event that does not leave at the second, w₁γ(½, c) + w₂γ(0.8, c) + (1 − w₀ − w₁ − w₂)γ(B_s, c),
    /// γ(B, c) = c(1 − B)/(1 − Bc), c the per-event survival. Guard: 1 − B_s c ≥ 10⁻⁶ (B_s < 1 by
    /// construction; c ≤ 1).
    ///
    /// This is the generating function of its events per unit of trapped light, for a per-event
    /// survival c (the conductor's Fresnel factor times the slab's round trip): a mixture of
    /// geometric event counts (B: the share that stays per event; w₀ the share that leaves at the
    /// second event, `glossy_once`) fitted by `glazec tables` to white walks through the reference's
    /// microsurfaces. At c = 1 it is 1 − w₀: a white conductor under a clear coat returns all of it.
    pub fn glossy_later(next: S, quick: S, steady: S, slow: S, c: V) -> V {
        let one = c.x().lit(1.0).splat();
        let quick_rate = c * 0.5 / (one - c * 0.5);
        let steady_rate = c * 0.2 / (one - c * 0.8);
        let slow_rate = c * slow.one_minus() / (c * slow).one_minus().max(c.x().lit(1e-6).splat());
        let rest = (next + quick + steady).one_minus().at_least(0.0);
        quick_rate * quick + steady_rate * steady + slow_rate * rest
    }
}

shading_fn! {
    /// glazec's glossy level, the light that leaves near the conductor's mirror direction, per
    /// unit entering: after one event (P₁) or, trapped, after the second (share w₀ of the
    /// trapped light, one more event's survival c): P₁ + (1 − P₁) w₀ c.
    pub fn glossy_once(single: S, next: S, c: V) -> V {
        c * (single.one_minus() * next) + single.splat()
    }
}

shading_fn! {
    /// glazec's glossy level, the directional albedo of the remainder, what leaves after more
    /// than one conductor event and not in the lobe: M(μ) = T a² F (1 − P₁) Ŷ, light that enters
    /// (T), is attenuated down and up once (a²) and reflected by the conductor (F, at the
    /// refracted direction), but not let out at once (1 − P₁) or in the lobe at the second event
    /// (w₀), and that its further events return (`glossy_later`).
    pub fn glossy_remainder(t: S, a: V, fresnel: V, single: S, later: V) -> V {
        a * a * fresnel * later * (t * single.one_minus())
    }
}

shading_fn! {
    /// Kulla & Conty 2017's reciprocal separable lobe for the glossy level's remainder: the light
    /// that leaves after several conductor events has forgotten the angle at which it entered,
    /// so f = M(μᵢ) M(μₒ)/(π ⟨M⟩), whose albedo is M(μₒ) exactly (⟨M⟩ = ∫ 2μ M(μ) dμ); the level
    /// spreads it over the azimuth ([`forward_azimuth_weight`]).
    /// Guard: ⟨M⟩ ≥ 10⁻⁶ (M ≡ 0 gives 0).
    pub fn glossy_remainder_lobe(m_i: V, m_o: V, m_avg: V) -> V {
        m_i * m_o / (m_avg.max(m_avg.x().lit(1e-6).splat()) * PI)
    }
}

shading_fn! {
    /// sin θl sin θv = |l_t| |v_t|, l_t and v_t the directions' components in the plane of `n`:
    /// what the forward spread's mean resultant length ρ = κ sin θl sin θv scales with (0 along
    /// the normal, where a direction has no azimuth). Guard: ≥ TINY (a direction along the
    /// normal; [`forward_cosine`] divides by it).
    pub fn forward_sines(n: V, v: V, l: V) -> S {
        let l_t = l - n * n.dot(l);
        let v_t = v - n * n.dot(v);
        (l_t.dot(l_t) * v_t.dot(v_t)).at_least(TINY).sqrt()
    }
}

shading_fn! {
    /// cos φf, φf the relative azimuth of `l` and `v` about the forward direction (φf = 0 where
    /// the light travels on as a mirror sends it): −l_t·v_t / (sin θl sin θv), `sines` from
    /// [`forward_sines`].
    pub fn forward_cosine(n: V, v: V, l: V, sines: S) -> S {
        let l_t = l - n * n.dot(l);
        let v_t = v - n * n.dot(v);
        -l_t.dot(v_t) / sines
    }
}

shading_fn! {
    /// The wrapped Cauchy distribution over the azimuth φf about the forward direction (Mardia & Jupp
    /// 2000, "Directional Statistics", §3.5.7): (1 − ρ²)/(1 + ρ² − 2ρ cos φf). Guard: ρ ≤ 0.95 (a
    /// narrower spread would need finer azimuths than a lobe has).
    ///
    /// ρ is its mean resultant length. Its mean over φf is 1 for every ρ ∈ [0, 1), so it moves a
    /// lobe's light between azimuths without changing its albedo; symmetric in l and v when ρ is.
    pub fn forward_azimuth_weight(rho: S, cos_phi: S) -> S {
        let r = rho.min(rho.lit(0.95));
        r.sq().one_minus() / (r.sq() + 1.0 - r * cos_phi * 2.0)
    }
}

shading_fn! {
    /// glazec's glossy level, after Mardia & Jupp 2000, §3.5.7 (the wrapped Cauchy's Fourier
    /// coefficients): the weight W of [`forward_azimuth_weight`] reweighted per channel to mean
    /// resultant lengths ρ_c by (1 + aV)/(1 + a⟨V⟩), V the wrapped Cauchy weight of ρ_b = ρ²,
    /// a = (ρ_c − ρ)(1 − x)/(ρ + ρ_b − ρ_c(1 + x)), x = ρρ_b. Guards: ρ ≤ 0.95, hence ρ_b ≤ 0.95; ρ_c
    /// below the reach at ρ_b = 0.95 less 10⁻³; the denominator ≥ 10⁻⁶; a ≥ −0.999(1 − ρ_b)/(1 + ρ_b),
    /// which keeps 1 + aV > 0 where V is largest.
    ///
    /// The light that took few conductor events, which a coloured conductor darkens least, is the
    /// light that kept going forward. The tilt's mean over W is 1 (albedo unchanged), with ⟨V⟩ =
    /// E_W[V] = (1 + x)/(1 − x), and the mean resultant length of W(1 + aV)/(1 + a⟨V⟩) is
    /// (ρ + a(ρ + ρ_b)/(1 − x))/(1 + a⟨V⟩) (W's and V's Fourier coefficients are ρ^|k| and ρ_b^|k|):
    /// equal to ρ_c for the a above. ρ_b = ρ² (V is W's own azimuth after a second, independent
    /// spread): measured against white walks weighed by cⁿ (`glazec-lab` example `spread_colour`), it
    /// darkens the sides and the back alike and keeps the boost within 45° of forward, as the walks
    /// do (coated_gold's conductor under its coat at 85°/75°, c 0.9: share of the coloured light per
    /// bin 1.14, 0.75, 0.58, 0.53, 0.52, 0.51 from forward to behind, the walks' 1.17, 0.82, 0.55,
    /// 0.46, 0.44, 0.44), where V = W (tilting towards W itself) kept 0.55 at the side and behind. A
    /// tilt towards V reaches at most (ρ + ρ_b)/(1 + x); where ρ_c needs more (low ρ, strong colour:
    /// in the body under η 2 coats) ρ_b grows to (ρ_t − ρ)/(1 − ρρ_t), the least that reaches
    /// ρ_t = ρ_c + 0.01, at most the reach at ρ_b = 0.95. The bound on a holds where V is largest,
    /// (1 + ρ_b)/(1 − ρ_b).
    pub fn forward_azimuth_tilt(rho: S, rho_c: V, cos_phi: S) -> V {
        let r = rho.min(rho.lit(0.95));
        let top = (r + 0.95) / (r * 0.95 + 1.0);
        let r_c = rho_c.min((top - 1e-3).splat());
        let target = (r_c + rho.lit(0.01).splat()).min(top.splat());
        let needed = (target - r.splat()) / (target * r).one_minus();
        let r_b = needed.max(r.sq().splat());
        let x = r_b * r;
        let one = rho.lit(1.0).splat();
        let mean_weight = (one + x) / (one - x);
        let denominator = ((r_b + r.splat()) - r_c * (one + x)).max(rho.lit(1e-6).splat());
        let least = (one - r_b) / (one + r_b) * -0.999;
        let a = ((r_c - r.splat()) * (one - x) / denominator).max(least);
        let weight = (one - r_b * r_b) / (one + r_b * r_b - r_b * cos_phi * 2.0);
        (one + a * weight) / (one + a * mean_weight)
    }
}

shading_fn! {
    /// glazec's glossy level: the forward spread's mean resultant length of light whose every
    /// conductor event keeps a share c of it, ρ_c = ρ · [L(cρ₁)/L(c)] / [L(ρ₁)/L(1)], ρ₁ = ρ^(1/n̄), L
    /// the later events' generating function (`glossy_later`) and n̄ their white mean count. Guards:
    /// n̄ from weights ≥ 10⁻⁶ and 1 − B_s ≥ 10⁻⁶; ρ ≥ 10⁻⁶ under the logarithm; L(c) and L(ρ₁) ≥ 10⁻⁶
    /// (a black channel has no remainder to spread).
    ///
    /// ρ is the white light's (the walks'). Each event keeps a direction's horizontal part with some
    /// scatter, so light that has taken n events has the azimuth of n steps of a random walk on the
    /// circle, of mean resultant length ρ₁ⁿ; coloured light weighs its event counts by cⁿ, short ones
    /// more, and so keeps going forward more than white light: under copper, light leaving backwards
    /// has taken the most events and is the darkest. L is a mixture of geometric counts, L(1) its
    /// total weight. ρ_c is exactly ρ for a white conductor (c = 1), and at most L(cρ₁)/L(c) < 1
    /// (E[ρ₁ⁿ] ≥ ρ₁^E[n], Jensen). It overstates the walks' own mean resultant length of coloured
    /// light (the walks' κ drops more slowly with the count than ρ₁ⁿ); it drives
    /// [`forward_azimuth_tilt`], and together they meet the reference best (docs/accuracy.md, "Coats
    /// over conductors").
    pub fn glossy_spread_colour(rho: S, next: S, quick: S, steady: S, slow: S, c: V) -> V {
        let rest = (next + quick + steady).one_minus().at_least(0.0);
        let weight = (quick + steady + rest).at_least(1e-6);
        let events = (quick * 2.0 + steady * 5.0 + rest / slow.one_minus().at_least(1e-6)) / weight;
        let per_event = (rho.at_least(1e-6).ln() / events).exp();
        let white = glossy_later(next, quick, steady, slow, per_event.splat()).x() / weight;
        let coloured = glossy_later(next, quick, steady, slow, c * per_event)
            / glossy_later(next, quick, steady, slow, c).max(rho.lit(1e-6).splat());
        coloured * (rho / white.at_least(1e-6))
    }
}

shading_fn! {
    /// The directional albedo seen above a coat over a conductor (glazec's glossy level):
    /// (1 − T) + T F (a₁² O + a² (1 − P₁) Ŷ): the coat's reflection, the lobe of light that
    /// leaves after one or two conductor events (`glossy_albedo_lobe`) and the remainder
    /// (`glossy_remainder`).
    pub fn glossy_albedo(t: S, lobe: V, remainder: V) -> V {
        lobe + remainder + t.one_minus().splat()
    }
}

shading_fn! {
    /// The part of `glossy_albedo` that leaves near the mirror direction as the lobe,
    /// T F a₁² O: light that leaves after one or two conductor events (O, `glossy_once`),
    /// attenuated by a₁² along its own paths.
    pub fn glossy_albedo_lobe(t: S, fresnel: V, a_lobe: V, once: V) -> V {
        fresnel * a_lobe * a_lobe * once * t
    }
}

shading_fn! {
    /// The directional albedo seen above a coat over a diffusing layer (same model as
    /// `interfaced_diffuse_under`): (1 − T) + T a E_below E_esc (x + c ρ̄ R / (1 − ρ̄ R)), where x
    /// and c scale the first reflection's escape and return against diffuse light's (both 1 for
    /// a diffusing body, which gives (1 − T) + T a E_below E_esc / (1 − ρ̄ R)).
    pub fn interfaced_albedo_dir(t: S, a: V, e_below: V, rho_below: V, r_return: V, e_escape: V, first_escape: V, first_return: V) -> V {
        let series = first_return * rho_below * r_return / (rho_below * r_return).one_minus();
        a * e_below * e_escape * (first_escape + series) * t + t.one_minus().splat()
    }
}

shading_fn! {
    /// The directional albedo seen above a coat over a glossy body (the model of
    /// `interfaced_glossy_under` and `trapped_lobe`): (1 − T) + T a² (N T + S T̄ + P X)/(1 − K k),
    /// k = (1 − T) a². Guard: 1 − K k ≥ 10⁻⁶ (0 where T = 0 over a white level, as in
    /// `interfaced_glossy_under`; the numerator is 0 there too).
    ///
    /// Of the body's reflection E, K = N + S stays inside the escape cone; its part N near the mirror
    /// direction leaves with T, the part S spread over the cone with the coat's transmission out of
    /// the cone T̄ (`transmission_from_cone`), and what the coat reflects comes back (k) to be
    /// reflected again. P, beyond the cone (`trapped_shares`), is trapped, and X of it leaves
    /// (`trapped_return`).
    pub fn interfaced_albedo_glossy(t: S, t_cone: S, a: V, near: V, spread: V, trapped: V, trapped_out: V) -> V {
        let leaving = near * t + spread * t_cone + trapped * trapped_out;
        a * a * interfaced_glossy_bounced(t, a, near + spread, leaving) * t + t.one_minus().splat()
    }
}

shading_fn! {
    /// What of `leaving`, light a glossy body sends up inside a coat's escape cone, comes back
    /// out through the coat's bounces, leaving / (1 − K k) (see `interfaced_albedo_glossy`).
    pub fn interfaced_glossy_bounced(t: S, a: V, kept: V, leaving: V) -> V {
        let k = a * a * t.one_minus();
        leaving / (kept * k).one_minus().max(t.lit(1e-6).splat())
    }
}

shading_fn! {
    /// glazec's interfaced layering, what leaves of the light a glossy body traps under a coat,
    /// per unit trapped (`trapped_lobe`'s albedo over Pᵢ): g ρ̄ q T̄/(1 − ρ̄ g (1 − q)), the body
    /// sending q of it into the cone at each bounce, and T̄ the coat's transmission out of the
    /// cone (at its mean cosine).
    pub fn trapped_return(round_trip: V, rho: V, q: S, t_cone: S) -> V {
        round_trip * rho * (q * t_cone) / (rho * round_trip * q.one_minus()).one_minus()
    }
}

shading_fn! {
    /// The hemispherical-average albedo seen above a coat (same model as `interfaced_layer`):
    /// ⟨E⟩ = E_F + η² E_esc(τ)² ρ̄ / (1 − ρ̄ᵣ R(τ)), where E_F = 1 − η² E_esc(0) is the coat's
    /// own average Fresnel reflectance (the flux identity 1 − E_F = η²(1 − K)) and ρ̄ᵣ the albedo
    /// for the light the coat returns (`returned_albedo`).
    pub fn interfaced_albedo(eta: S, e_escape_clear: S, e_escape: V, r_return: V, rho_below: V, rho_returned: V) -> V {
        let eta_sq = eta * eta;
        let e_fresnel = (eta_sq * e_escape_clear).one_minus();
        e_escape * e_escape * rho_below * eta_sq / (rho_returned * r_return).one_minus() + e_fresnel.splat()
    }
}
