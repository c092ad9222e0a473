//! The library's own enums as command-line choices: clap offers their names and help, and parses
//! straight into the library type (no mirror enums in the CLI).

use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};

/// A library enum offered on the command line.
pub trait Choice: Copy + Send + Sync + 'static {
    const ALL: &'static [Self];
    fn name(self) -> &'static str;
    fn help(self) -> &'static str {
        ""
    }
}

/// The value parser of a [`Choice`]: its names as the possible values.
pub fn parser<T: Choice>() -> impl TypedValueParser<Value = T> {
    PossibleValuesParser::new(T::ALL.iter().map(|t| PossibleValue::new(t.name()).help(t.help()))).try_map(
        |name: String| {
            // PossibleValuesParser has already refused any other name.
            T::ALL.iter().copied().find(|t| t.name() == name).ok_or_else(|| format!("unknown value `{name}`"))
        },
    )
}

/// A library enum with `ALL`, `name()` and `description()` is a [`Choice`] as it is.
macro_rules! library_choice {
    ($t:ty) => {
        impl Choice for $t {
            const ALL: &'static [Self] = &<$t>::ALL;
            fn name(self) -> &'static str {
                <$t>::name(self)
            }
            fn help(self) -> &'static str {
                <$t>::description(self)
            }
        }
    };
}

library_choice!(glazec::Target);
#[cfg(feature = "lab")]
library_choice!(glazec_lab::reference::InterfaceMode);
#[cfg(feature = "gpu")]
library_choice!(glazec_gpu::preview::Environment);
