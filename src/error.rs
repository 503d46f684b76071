//! Errors that every layer may raise.

use std::fmt;

/// An error about one of the caller's options (a limit reached, a value that
/// does not fit), with the option named by its field in the library's options
/// structs: `max_polygons`, `format`, `crop`. The text is kept in three parts
/// so that a front end can put its own name for the option in its place (the
/// tools put their flag, `--max-polygons`); [`fmt::Display`] uses the field.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct OptionError {
    /// The text before the option's name.
    pub before: String,
    /// The option, as its field is named in the library.
    pub option: &'static str,
    /// The text after the option's name.
    pub after: String,
}

impl OptionError {
    /// `before` + the option's name + `after`.
    pub fn new(
        before: impl Into<String>,
        option: &'static str,
        after: impl Into<String>,
    ) -> OptionError {
        OptionError {
            before: before.into(),
            option,
            after: after.into(),
        }
    }

    /// The message with the option called `name`.
    pub fn worded(&self, name: &str) -> String {
        format!("{}{name}{}", self.before, self.after)
    }
}

impl fmt::Display for OptionError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.worded(self.option))
    }
}

impl std::error::Error for OptionError {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_option_can_be_named_by_the_caller() {
        let e = OptionError::new("past ", "max_polygons", " 10");
        assert_eq!(e.to_string(), "past max_polygons 10");
        assert_eq!(e.worded("--max-polygons"), "past --max-polygons 10");
    }
}
