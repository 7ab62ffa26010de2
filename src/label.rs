//! Closed sets with a text label: the one place an enum's members get the
//! names users see in tables, JSON, pipeline files, on the command line and
//! in Python. Every view of a closed set is derived from here: the command
//! line's value parsers (its possible values and their help), the
//! deserialisers of the request types that Python's keyword arguments and
//! pipelines land in ([`deserialize_by_label!`](crate::deserialize_by_label)),
//! the table columns, the generated references.

/// A closed set whose members each have one label.
pub trait Label: Copy + PartialEq + 'static {
    /// Every member, in the order the docs list them.
    const ALL: &'static [Self];
    /// What a member is, for messages: "model", "integrator".
    const WHAT: &'static str = "value";
    fn label(self) -> &'static str;

    /// One line saying what the member means (the command line's help of
    /// each possible value); empty when the label says it all.
    fn help(self) -> &'static str {
        ""
    }

    /// Other spellings accepted on input (`linearised` for `linearized`).
    fn aliases(self) -> &'static [&'static str] {
        &[]
    }

    /// The member with this label.
    fn from_label(text: &str) -> Option<Self> {
        Self::ALL.iter().copied().find(|m| m.label() == text)
    }

    /// The member with this label or one of its aliases, or a message that
    /// names the set and lists the valid labels.
    fn parse_label(text: &str) -> Result<Self, String> {
        let t = text.trim();
        Self::ALL
            .iter()
            .copied()
            .find(|m| m.label() == t || m.aliases().contains(&t))
            .ok_or_else(|| format!("unknown {} `{text}`; valid: {}", Self::WHAT, Self::labels()))
    }

    /// "a, b, c": the valid labels, for error messages.
    fn labels() -> String {
        Self::ALL
            .iter()
            .map(|m| m.label())
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// Implements `serde::Deserialize` for closed sets by their labels
/// ([`Label::parse_label`]), so that a request type with such a field
/// takes a pipeline's or Python's text and refuses a wrong one with the
/// valid labels.
#[macro_export]
macro_rules! deserialize_by_label {
    ($($t:ty),* $(,)?) => {$(
        impl<'de> ::serde::Deserialize<'de> for $t {
            fn deserialize<D: ::serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
                let text = <::std::string::String as ::serde::Deserialize>::deserialize(d)?;
                <$t as $crate::label::Label>::parse_label(&text).map_err(::serde::de::Error::custom)
            }
        }
    )*};
}

/// Implements `serde::Deserialize` through `FromStr`, for the open sets
/// that have a text form (an IM, an overturning criterion).
#[macro_export]
macro_rules! deserialize_by_from_str {
    ($($t:ty),* $(,)?) => {$(
        impl<'de> ::serde::Deserialize<'de> for $t {
            fn deserialize<D: ::serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
                let text = <::std::string::String as ::serde::Deserialize>::deserialize(d)?;
                text.parse::<$t>().map_err(::serde::de::Error::custom)
            }
        }
    )*};
}
