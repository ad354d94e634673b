//! What every command of the `taut` command line shares: the file flags (`--up`, `--force`), the
//! refusal to write over an input, and errors and notes that keep stderr to one line.
//!
//! The README promises that every error is one line on stderr with a non-zero exit. So notes
//! (what an import repaired, a λ reduced after divergence) go to stdout, argument errors are
//! folded into one line, and the GPU loader is given a private runtime folder when the session
//! has none (it complains otherwise, twice per render).

use clap::Args;
use std::path::Path;
use taut_core::io::{ExportOptions, ImportOptions, UpAxis};

/// Flags of every command that reads and writes mesh files.
#[derive(Debug, Args, Clone, Copy)]
pub struct FileFlags {
    /// The up axis of OBJ files read and written: y (Blender's and most tools' default) or z
    /// (Taut's own axes). glTF is always Y up.
    #[arg(long, default_value = "y", value_name = "y|z")]
    pub up: UpAxis,
    /// Write the output even when it is one of the input files.
    #[arg(long)]
    pub force: bool,
}

impl FileFlags {
    pub fn import_options(&self) -> ImportOptions {
        ImportOptions { obj_up: self.up }
    }

    pub fn export_options<'a>(&self, normals: Option<&'a [taut_core::DVec3]>) -> ExportOptions<'a> {
        ExportOptions { normals, obj_up: self.up }
    }

    /// Refuses to write `output` over one of `inputs` (the same file once links are followed,
    /// hard links included) unless `--force` was given.
    pub fn check_output(&self, inputs: &[&Path], output: &Path) -> Result<(), String> {
        check_output(self.force, inputs, output)
    }
}

/// Refuses, before any work is done, an `output` that cannot take the result (a device, a FIFO, a
/// folder, a read-only file, a missing folder) and, unless `force`, one that is one of `inputs`.
/// A command with several outputs checks every one before it writes any.
pub fn check_output(force: bool, inputs: &[&Path], output: &Path) -> Result<(), String> {
    taut_core::io::file::check_writable(output).map_err(|e| e.to_string())?;
    if force {
        return Ok(());
    }
    match inputs.iter().find(|input| taut_core::io::file::same_file(input, output)) {
        Some(input) => Err(format!(
            "{} is the input file {}: writing it would replace the input; choose another output or add --force",
            output.display(),
            input.display()
        )),
        None => Ok(()),
    }
}

/// Writes several outputs together: `write` writes `outputs` in turn; when it fails part way,
/// each output is put back as it was (the earlier file, or none), so a command writes all its
/// outputs or none of them. Earlier files are kept aside by a hard link beside them (a copy
/// where the folder cannot link), which the atomic writes leave untouched as they rename new
/// files over the paths; the links go once every output is written.
pub fn all_or_none(outputs: &[&Path], write: impl FnOnce() -> Result<(), String>) -> Result<(), String> {
    let mut kept: Vec<(&Path, Option<std::path::PathBuf>)> = Vec::new();
    let forget = |kept: &[(&Path, Option<std::path::PathBuf>)]| {
        for (_, aside) in kept {
            if let Some(aside) = aside {
                let _ = std::fs::remove_file(aside);
            }
        }
    };
    for (k, &path) in outputs.iter().enumerate() {
        let aside = match std::fs::symlink_metadata(path) {
            Ok(meta) if meta.is_file() || meta.is_symlink() => {
                let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
                let aside = path.with_file_name(format!(".{name}.kept-{}-{k}", std::process::id()));
                let _ = std::fs::remove_file(&aside);
                if std::fs::hard_link(path, &aside).is_err()
                    && let Err(e) = std::fs::copy(path, &aside)
                {
                    forget(&kept);
                    return Err(format!("{}: cannot keep the earlier file aside while writing ({e})", path.display()));
                }
                Some(aside)
            }
            _ => None,
        };
        kept.push((path, aside));
    }
    let result = write();
    if result.is_err() {
        for (path, aside) in &kept {
            match aside {
                Some(aside) => {
                    let _ = std::fs::rename(aside, path);
                }
                None => {
                    let _ = std::fs::remove_file(path);
                }
            }
        }
    }
    forget(&kept);
    result
}

/// A clap error as one line: its message with the items it lists, its tip, and where to read
/// more; the usage block is left out.
pub fn one_line(error: &clap::Error) -> String {
    let rendered = error.to_string();
    let mut message = String::new();
    let mut tips = Vec::new();
    for line in rendered.lines().map(str::trim).filter(|l| !l.is_empty()) {
        if line.starts_with("Usage:") || line.starts_with("For more information") {
            break;
        }
        if let Some(tip) = line.strip_prefix("tip:") {
            tips.push(tip.trim().to_string());
        } else if message.is_empty() {
            message = line.trim_start_matches("error:").trim().to_string();
        } else {
            // The items of a list ("the following required arguments were not provided:").
            let sep = if message.ends_with(':') { " " } else { ", " };
            message = format!("{message}{sep}{line}");
        }
    }
    if message.is_empty() {
        message = "invalid arguments".into();
    }
    let tip = if tips.is_empty() { String::new() } else { format!(" ({})", tips.join("; ")) };
    format!("{message}{tip}; see taut --help")
}

/// Longest quoted value an error repeats before it is cut short.
pub const MAX_QUOTED_CHARS: usize = 48;

/// An error message with every quoted value ('…', `…` or "…") longer than
/// [`MAX_QUOTED_CHARS`] cut short, and the whole at most 1,000 characters, so that a refusal of a
/// hostile file (a 500 MB value in a `.taut`) stays one short line.
pub fn clip_quotes(message: &str) -> String {
    let chars: Vec<char> = message.chars().collect();
    let word = |k: Option<&char>| k.is_some_and(|c| c.is_alphanumeric());
    let mut out = String::with_capacity(message.len().min(1100));
    let mut quote: Option<(char, usize)> = None;
    for (k, &c) in chars.iter().enumerate() {
        let before = k.checked_sub(1).and_then(|b| chars.get(b));
        match quote {
            // An apostrophe inside a word ("Taut's") neither opens nor closes a quote.
            Some((q, _)) if c == q && !(q == '\'' && word(chars.get(k + 1))) => {
                quote = None;
                out.push(c);
            }
            Some((q, n)) => {
                if n < MAX_QUOTED_CHARS {
                    out.push(c);
                } else if n == MAX_QUOTED_CHARS {
                    out.push('…');
                }
                quote = Some((q, n + 1));
            }
            None => {
                if matches!(c, '\'' | '`' | '"') && !word(before) {
                    quote = Some((c, 0));
                }
                out.push(c);
            }
        }
        if out.chars().count() >= 1000 {
            out.push('…');
            break;
        }
    }
    out
}

/// A note for the designer: on stdout, so stderr keeps only the one line of an error.
pub fn note(text: impl std::fmt::Display) {
    println!("note: {text}");
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_failing_second_output_puts_the_first_back() {
        let dir = std::env::temp_dir().join(format!("taut-all-or-none-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let (old, new, second) = (dir.join("old.obj"), dir.join("new.obj"), dir.join("report.json"));
        std::fs::write(&old, "earlier").unwrap();
        for first in [&old, &new] {
            let result = all_or_none(&[first, &second], || {
                taut_core::io::write_atomic(first, b"replaced").map_err(|e| e.to_string())?;
                Err("the report could not be written".to_string())
            });
            assert_eq!(result.unwrap_err(), "the report could not be written");
        }
        assert_eq!(std::fs::read_to_string(&old).unwrap(), "earlier", "the earlier file is back");
        assert!(!new.exists() && !second.exists(), "nothing new is left");
        // Nothing kept aside is left over, and a write that succeeds keeps both outputs.
        all_or_none(&[&old, &second], || {
            taut_core::io::write_atomic(&old, b"one").map_err(|e| e.to_string())?;
            taut_core::io::write_atomic(&second, b"two").map_err(|e| e.to_string())
        })
        .unwrap();
        assert_eq!(std::fs::read_to_string(&old).unwrap(), "one");
        assert_eq!(std::fs::read_to_string(&second).unwrap(), "two");
        let mut names: Vec<String> =
            std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
        names.sort();
        assert_eq!(names, ["old.obj", "report.json"]);
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn long_quoted_values_are_cut_short() {
        let huge = "x".repeat(10_000);
        let clipped = clip_quotes(&format!("format is '{huge}', expected 'taut'"));
        assert_eq!(clipped, format!("format is '{}…', expected 'taut'", "x".repeat(MAX_QUOTED_CHARS)));
        let apostrophes = format!("the cage's vertex 3 is {}; Taut's rule", "far ".repeat(30));
        assert_eq!(clip_quotes(&apostrophes), apostrophes);
        let unquoted = "y ".repeat(5_000);
        assert!(clip_quotes(&unquoted).chars().count() <= 1001);
    }
}
