//! `clap::ValueEnum` for the library's closed sets, behind the `clap`
//! feature: the command line takes its names and its list of choices from
//! the library types themselves (strum's derived `VARIANTS` and names), so
//! there is no mirror enum to keep in step.

use clap::builder::PossibleValue;
use clap::ValueEnum;

macro_rules! value_enum {
    ($($t:ty),* $(,)?) => {$(
        impl ValueEnum for $t {
            fn value_variants<'a>() -> &'a [Self] {
                <$t as strum::VariantArray>::VARIANTS
            }

            fn to_possible_value(&self) -> Option<PossibleValue> {
                Some(PossibleValue::new(<&'static str>::from(*self)))
            }
        }
    )*};
}

value_enum!(
    crate::sampling::SamplerKind,
    crate::filter::FilterKind,
    crate::light::LightShape,
    crate::accel::AccelKind,
);
