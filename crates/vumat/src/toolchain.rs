//! The compilers: gfortran for the user's file (and as the linker, which brings in
//! libgfortran), the C compiler for the adapter. `$FC` and `$CC` name others.

use std::ffi::OsStr;
use std::process::Command;

use crate::error::VumatError;

/// A compiler and the environment variable that overrides it.
#[derive(Debug, Clone)]
pub struct Tool {
    pub program: String,
    pub variable: &'static str,
}

impl Tool {
    /// `$FC`, else `gfortran`.
    pub fn fortran() -> Tool {
        Tool::from_env("FC", "gfortran")
    }

    /// `$CC`, else `cc`.
    pub fn c() -> Tool {
        Tool::from_env("CC", "cc")
    }

    fn from_env(variable: &'static str, default: &str) -> Tool {
        let program = std::env::var(variable)
            .ok()
            .filter(|v| !v.trim().is_empty())
            .unwrap_or_else(|| default.to_string());
        Tool { program, variable }
    }

    /// Whether the program runs at all (`--version`).
    pub fn is_available(&self) -> bool {
        Command::new(&self.program)
            .arg("--version")
            .output()
            .is_ok_and(|o| o.status.success())
    }

    /// Run the tool with `args` in the current directory (so that its messages name the
    /// user's file as the user named it): `Ok(Ok(output))` when it succeeded,
    /// `Ok(Err(output))` when it ran and failed (stderr then stdout, as the user would
    /// see them), `Err` when it could not be started.
    pub fn run(&self, args: &[&OsStr]) -> Result<Result<String, String>, VumatError> {
        let output = Command::new(&self.program)
            .args(args)
            .output()
            .map_err(|e| match e.kind() {
                std::io::ErrorKind::NotFound => VumatError::ToolMissing {
                    tool: self.program.clone(),
                    variable: self.variable,
                },
                _ => VumatError::Io {
                    what: "run".into(),
                    path: self.program.clone().into(),
                    source: e,
                },
            })?;
        let mut text = String::from_utf8_lossy(&output.stderr).into_owned();
        text.push_str(&String::from_utf8_lossy(&output.stdout));
        Ok(if output.status.success() {
            Ok(text)
        } else {
            Err(text)
        })
    }
}

/// The symbols a linker reports as undefined (GNU ld: "undefined reference to `name'";
/// lld and macOS ld: "undefined symbol: name" / "_name"), each once, in order.
pub fn undefined_symbols(linker_output: &str) -> Vec<String> {
    let mut names: Vec<String> = Vec::new();
    for line in linker_output.lines() {
        let name = if let Some((_, rest)) = line.split_once("undefined reference to `") {
            rest.split('\'').next()
        } else if let Some((_, rest)) = line.split_once("undefined symbol: ") {
            Some(rest.trim().trim_start_matches('_'))
        } else {
            None
        };
        if let Some(name) = name.map(str::trim).filter(|n| !n.is_empty())
            && !names.iter().any(|n| n == name)
        {
            names.push(name.to_string());
        }
    }
    names
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn undefined_symbols_are_read_from_gnu_ld_and_lld_output() {
        let gnu = "/usr/bin/ld: vumat.o: in function `vumat_':\n\
                   vumat.f:(.text+0x2c): undefined reference to `vgetjobname_'\n\
                   /usr/bin/ld: vumat.f:(.text+0x40): undefined reference to `vgetjobname_'\n\
                   collect2: error: ld returned 1 exit status";
        assert_eq!(undefined_symbols(gnu), ["vgetjobname_"]);
        let lld = "ld.lld: error: undefined symbol: vumat_\n>>> referenced by adapter.c";
        assert_eq!(undefined_symbols(lld), ["vumat_"]);
        assert!(undefined_symbols("all fine").is_empty());
    }
}
