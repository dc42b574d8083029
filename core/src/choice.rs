//! Closed sets of named values: the spaces, limit modes, ends and linear solvers (and, above
//! this crate, the co-design's methods and rules), each value with the one name that task files,
//! result files, flags and Python keywords spell it with.

/// A type with a fixed list of values, each known by one lower-case name.
///
/// ```
/// use codesign_core::choice::Choice;
/// use codesign_core::problem::Space;
///
/// assert_eq!(Space::from_name("joint"), Some(Space::Joint));
/// assert_eq!(Space::names(), ["joint", "actuation"]);
/// assert_eq!(Space::from_name("Joint"), None);
/// ```
pub trait Choice: Copy + Send + Sync + 'static {
    /// Every value, in the order help texts list them.
    const ALL: &'static [Self];

    /// The name of this value.
    fn name(self) -> &'static str;

    /// The value called `name` (exactly, case included), if any.
    fn from_name(name: &str) -> Option<Self> {
        Self::ALL.iter().copied().find(|value| value.name() == name)
    }

    /// The names of [`Choice::ALL`], in order.
    fn names() -> Vec<&'static str> {
        Self::ALL.iter().map(|value| value.name()).collect()
    }
}
