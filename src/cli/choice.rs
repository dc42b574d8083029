//! Flags whose value is one of a closed set of names ([`Choice`]: `--space`, `--ends`,
//! `--linear-solver`, ...): parsed and listed in `--help` by clap, while the types themselves,
//! below the command line, know nothing of clap.

use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
use codesign_core::choice::Choice;
use std::ffi::OsStr;
use std::marker::PhantomData;

/// The parser of a flag that takes one value of `T` by its name.
#[derive(Clone, Copy, Debug)]
pub struct ChoiceParser<T>(PhantomData<T>);

/// The parser of a flag that takes one value of `T` by its name: `value_parser = choice::<Space>()`.
pub fn choice<T: Choice>() -> ChoiceParser<T> {
    ChoiceParser(PhantomData)
}

impl<T: Choice> TypedValueParser for ChoiceParser<T> {
    type Value = T;

    fn parse_ref(
        &self,
        cmd: &clap::Command,
        arg: Option<&clap::Arg>,
        value: &OsStr,
    ) -> Result<T, clap::Error> {
        // clap's own parser of the names writes the usual error (the value, the names, a
        // suggestion); a name it accepts is one of T's.
        let name = PossibleValuesParser::new(T::names()).parse_ref(cmd, arg, value)?;
        T::from_name(&name).ok_or_else(|| clap::Error::new(clap::error::ErrorKind::InvalidValue))
    }

    fn possible_values(&self) -> Option<Box<dyn Iterator<Item = PossibleValue> + '_>> {
        Some(Box::new(
            T::ALL.iter().map(|value| PossibleValue::new(value.name())),
        ))
    }
}
