//! Random layer stacks for property tests: 1..=8 coats with every lobe, base and method, each
//! number a literal or a runtime parameter, written out as material text.

use proptest::prelude::*;

/// Index of `WeidlichWilkie` in [`Stack::method`] (0 = default, 1 = Additive, 3 = Interfaced,
/// 4 and 5 = its Schlick-Fresnel and single-scattering approximations).
pub const WEIDLICH_WILKIE: u8 = 2;

#[derive(Debug, Clone)]
pub enum Num {
    Lit(f32),
    Param(f32),
}

fn num(range: std::ops::RangeInclusive<f32>) -> impl Strategy<Value = Num> {
    prop_oneof![4 => range.clone().prop_map(Num::Lit), 1 => range.prop_map(Num::Param)]
}

fn rgb(range: std::ops::RangeInclusive<f32>) -> impl Strategy<Value = (Num, [f32; 3])> {
    (num(range.clone()), prop::array::uniform3(range))
}

#[derive(Debug, Clone)]
pub struct Coat {
    pub lobe: u8,
    pub roughness: Num,
    pub ior: Num,
    pub absorption: (Num, [f32; 3]),
    pub thickness: Num,
}

#[derive(Debug, Clone)]
pub struct Stack {
    pub method: u8,
    pub coats: Vec<Coat>,
    pub base: u8,
    pub albedo: (Num, [f32; 3]),
    pub roughness: Num,
    pub ior: Num,
}

pub fn coat() -> impl Strategy<Value = Coat> {
    (0u8..3, num(0.0..=1.0), num(0.7..=3.0), rgb(0.0..=5.0), num(0.0..=2.0))
        .prop_map(|(lobe, roughness, ior, absorption, thickness)| Coat { lobe, roughness, ior, absorption, thickness })
}

pub fn stack() -> impl Strategy<Value = Stack> {
    stack_of(1..=8)
}

/// Stacks with a given range of coat counts (up to glazec's limit of 16).
pub fn stack_of(coats: std::ops::RangeInclusive<usize>) -> impl Strategy<Value = Stack> {
    (0u8..6, prop::collection::vec(coat(), coats), 0u8..6, rgb(0.0..=1.0), num(0.0..=1.0), num(1.05..=2.5))
        .prop_map(|(method, coats, base, albedo, roughness, ior)| Stack { method, coats, base, albedo, roughness, ior })
}

impl Stack {
    /// The same stack with every runtime parameter replaced by its value.
    pub fn literal(mut self) -> Stack {
        let lit = |n: &mut Num| {
            if let Num::Param(x) = *n {
                *n = Num::Lit(x);
            }
        };
        for coat in &mut self.coats {
            lit(&mut coat.roughness);
            lit(&mut coat.ior);
            lit(&mut coat.absorption.0);
            lit(&mut coat.thickness);
        }
        lit(&mut self.albedo.0);
        lit(&mut self.roughness);
        lit(&mut self.ior);
        self
    }
}

/// Writes a stack as material text; runtime parameters get unique names.
pub struct Writer {
    pub next_param: usize,
}

impl Writer {
    fn num(&mut self, n: &Num) -> String {
        match n {
            Num::Lit(x) => format!("{x:?}"),
            Num::Param(x) => {
                self.next_param += 1;
                format!("Param(\"p{}\", {x:?})", self.next_param)
            }
        }
    }

    fn rgb(&mut self, (n, c): &(Num, [f32; 3])) -> String {
        match n {
            Num::Lit(_) => format!("({:?}, {:?}, {:?})", c[0], c[1], c[2]),
            Num::Param(_) => {
                self.next_param += 1;
                format!("Param(\"p{}\", ({:?}, {:?}, {:?}))", self.next_param, c[0], c[1], c[2])
            }
        }
    }

    pub fn material(&mut self, s: &Stack) -> String {
        let method = [
            "",
            "method: Additive,",
            "method: WeidlichWilkie,",
            "method: Interfaced,",
            "method: Interfaced(fresnel: Schlick),",
            "method: Interfaced(multiple_scattering: false),",
        ][s.method as usize];
        let mut layers = Vec::new();
        for c in &s.coats {
            let lobe = match c.lobe {
                0 => "Smooth".to_string(),
                1 => format!("Ggx(roughness: {})", self.num(&c.roughness)),
                _ => format!("Gtr1({})", self.num(&c.roughness)),
            };
            layers.push(format!(
                "Coat(lobe: {lobe}, ior: {}, absorption: {}, thickness: {})",
                self.num(&c.ior),
                self.rgb(&c.absorption),
                self.num(&c.thickness)
            ));
        }
        let base = match s.base {
            0 => format!("Lambert({})", self.rgb(&s.albedo)),
            1 => format!("OrenNayar(albedo: {}, roughness: {})", self.rgb(&s.albedo), self.num(&s.roughness)),
            2 => format!("Eon(albedo: {}, roughness: {})", self.rgb(&s.albedo), self.num(&s.roughness)),
            3 => format!("Conductor(roughness: {}, f0: {})", self.num(&s.roughness), self.rgb(&s.albedo)),
            4 => format!("Conductor(roughness: {}, eta: (0.2, 0.9, 1.1), k: (3.9, 2.4, 2.1))", self.num(&s.roughness)),
            _ => format!(
                "Plastic(albedo: {}, roughness: {}, ior: {})",
                self.rgb(&s.albedo),
                self.num(&s.roughness),
                self.num(&s.ior)
            ),
        };
        layers.push(base);
        format!("Material(name: \"random\", {method} layers: [\n    {}\n])", layers.join(",\n    "))
    }
}

/// Whether glazec refused the stack only because its runtime lookups would need more tables
/// than a uniform binding holds (E0222): a random stack with many runtime parameters can, and
/// the refusal is the right answer for it.
pub fn refused_for_table_budget(error: &glazec::CompileError) -> bool {
    match error {
        glazec::CompileError::Diagnostics(d) => {
            !d.is_empty() && d.iter().all(|d| d.code == glazec::diag::Code::TableBudget)
        }
        glazec::CompileError::Internal(_) => false,
    }
}
