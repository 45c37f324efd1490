//! Errors of the file layer: a text's placeholders ([`TextError`]) and a key path set in a
//! merged table ([`OverrideError`]). Each says what is wrong; the caller names the file and
//! key ([`super::Error::refused`]).

/// The syntax, for error messages.
pub const SYNTAX: &str = "placeholders {ID}, {ID.FIELD}, {MODEL/ID}, {EXPERIMENT#ID} or {@EXPERIMENT.EXPORT}, each optionally followed by :N (N decimals) or :N% (a ratio as a signed change in per cent), e.g. {ratio:2}";

/// Why a text does not parse (the caller names the file and key).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum TextError {
    /// A '{' never closed.
    #[error("an unclosed '{{' at \"{0}\"; {SYNTAX}")]
    Unclosed(String),
    /// A '}' never opened.
    #[error("a '}}' without '{{' in \"{0}\"; {SYNTAX}")]
    Unopened(String),
    /// A placeholder that is not one.
    #[error("{text}: {why}; {SYNTAX}")]
    Placeholder {
        /// The placeholder with its braces.
        text: String,
        /// What is wrong with it.
        why: &'static str,
    },
}

/// Why a key path cannot be read or set (the caller names the file and key).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum OverrideError {
    /// Not a key path.
    #[error("{PATH_SYNTAX}")]
    Syntax,
    /// The path selects nothing.
    #[error("the path selects no value (an empty list?)")]
    SelectsNothing,
    /// A name on the way is not a key of its table.
    #[error("no key \"{name}\" here (the keys are {keys:?})")]
    NoKey {
        /// The name.
        name: String,
        /// The table's keys.
        keys: Vec<String>,
    },
    /// A selector on something that is not a list.
    #[error("\"{name}\" is a {found}, not a list")]
    NotAList {
        /// The name.
        name: String,
        /// What it is.
        found: &'static str,
    },
    /// A name on the way to the last holds no table.
    #[error("\"{name}\" holds a {found}, not a table")]
    NotATable {
        /// The name.
        name: String,
        /// What it holds.
        found: &'static str,
    },
    /// An index past the list's end.
    #[error("\"{name}\" has {len} elements; index {index} is out of range (0-based)")]
    OutOfRange {
        /// The list's name.
        name: String,
        /// Its length.
        len: usize,
        /// The index asked for.
        index: usize,
    },
    /// No element with the id asked for.
    #[error("no element of \"{name}\" has id \"{id}\" (the ids are {ids:?})")]
    NoId {
        /// The list's name.
        name: String,
        /// The id asked for.
        id: String,
        /// The ids there are.
        ids: Vec<String>,
    },
    /// A number set on a list of other things.
    #[error("a list that is not of numbers: select an element with [INDEX]")]
    NotNumbers,
    /// A number set on a table.
    #[error("a table, not a number: give the path of one of its keys")]
    TableNotNumber,
}

/// What a key path is, for messages.
pub const PATH_SYNTAX: &str = "names of letters, digits and '_' separated by '.', each optionally followed by \
                               [INDEX], [*] or [ID], e.g. \"cases[*].dampers[*].clearance_mm\"";
