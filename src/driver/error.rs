//! How a command ends. Every command returns `Result<Outcome, CliError>`; `main` turns
//! that into the process's exit code with [`exit_code`], the one place that knows the
//! numbers: 0 ok (warnings allowed), 1 invalid input, 2 usage or I/O error.

use std::fmt;

/// A command that ran to its end.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Outcome {
    /// Everything asked for was done (exit 0).
    Done,
    /// The command ran, and what it reports is a finding, not a failure of mapc (exit 1):
    /// `mapc diff` found changes.
    Differs,
    /// `mapc sim` stopped at a signal after writing what ran (exit 130, as a shell's).
    Interrupted,
}

/// Why a command failed.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) enum CliError {
    /// Wrong arguments or an I/O failure (exit 2); `main` prints `error: MESSAGE`.
    Usage(String),
    /// The input is invalid (exit 1); `main` prints `error: MESSAGE`.
    Invalid(String),
    /// The input is invalid and the command has said why already (exit 1).
    InvalidReported,
    /// A usage or I/O failure the command has reported already, having carried on with
    /// its other inputs (exit 2).
    UsageReported,
}

impl CliError {
    /// The message `main` prints, if the command has not said it.
    pub(crate) fn message(&self) -> Option<&str> {
        match self {
            CliError::Usage(m) | CliError::Invalid(m) => Some(m),
            CliError::InvalidReported | CliError::UsageReported => None,
        }
    }
}

impl fmt::Display for CliError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.message().unwrap_or("(reported above)"))
    }
}

/// Any plain `String` error of the driver (reading, writing, arguments) is a usage or I/O
/// error: invalid input is always said as diagnostics first.
impl From<String> for CliError {
    fn from(m: String) -> CliError {
        CliError::Usage(m)
    }
}

/// The exit code of a command's result: the only place that knows the numbers.
pub(crate) fn exit_code(r: &Result<Outcome, CliError>) -> u8 {
    match r {
        Ok(Outcome::Done) => 0,
        Ok(Outcome::Differs) => 1,
        Ok(Outcome::Interrupted) => 130,
        Err(CliError::Invalid(_) | CliError::InvalidReported) => 1,
        Err(CliError::Usage(_) | CliError::UsageReported) => 2,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exit_codes() {
        assert_eq!(exit_code(&Ok(Outcome::Done)), 0);
        assert_eq!(exit_code(&Err(CliError::InvalidReported)), 1);
        assert_eq!(exit_code(&Err("x".to_string().into())), 2);
        assert_eq!(exit_code(&Err(CliError::UsageReported)), 2);
    }
}
