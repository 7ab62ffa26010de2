//! Closed sets with a text label: the one place an enum's members get the
//! names users see in tables, JSON and pipeline files.

/// A closed set whose members each have one label.
pub trait Label: Copy + PartialEq + 'static {
    /// Every member, in the order the docs list them.
    const ALL: &'static [Self];
    fn label(self) -> &'static str;

    /// The member with this label.
    fn from_label(text: &str) -> Option<Self> {
        Self::ALL.iter().copied().find(|m| m.label() == text)
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
