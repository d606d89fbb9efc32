//! Property test over scene files (issue: reliability): the examples, edited at random the
//! way a user or a broken script edits them (a number replaced by 0, a negative, a huge or
//! tiny one, NaN or infinity; a line deleted or repeated; the file cut short; one key's
//! name put in another's place), are either refused with an error that names the file, or
//! built into a model; never a panic. Small implicit models that build are run, and
//! whatever they return at exit must be finite.
//!
//! Cases: 160 per run (`PROPTEST_CASES` changes it); a failure is shrunk to a smallest
//! edit list and printed, not stored. The counts of each outcome are printed.

use std::cell::RefCell;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use proptest::prelude::*;
use proptest::test_runner::TestRunner;

use musclefem_core::solver::Analysis;
use musclefem_core::solver::observer::NoObserver;
use musclefem_io::scene::{build_model, parse_scene};
use musclefem_materials::MaterialLibrary;

const EXAMPLES: [&str; 4] = [
    "neo_hookean_cube_stretch.toml",
    "hill_block_isometric.toml",
    "block_on_rigid_sphere.toml",
    "bonded_blocks_peel.toml",
];

/// Numbers a careless edit leaves behind (TOML spells the non-finite ones nan and inf).
const NUMBERS: [&str; 12] = [
    "0", "0.0", "-1", "-0.5", "2.5", "7", "1e9", "1e300", "1e-300", "nan", "inf", "-inf",
];

/// Keys of the scene format, for swapping one's name for another's.
const KEYS: [&str; 12] = [
    "name",
    "model",
    "material",
    "element",
    "density",
    "mesh",
    "divisions",
    "value",
    "amplitude",
    "duration",
    "components",
    "nodes",
];

#[derive(Debug, Clone)]
enum Edit {
    /// Replace the n-th number literal (modulo their count) by one of [`NUMBERS`].
    Number(usize, usize),
    /// Delete the n-th line.
    DeleteLine(usize),
    /// Repeat the n-th line.
    RepeatLine(usize),
    /// Cut the file at the n-th byte (on a character boundary).
    Truncate(usize),
    /// Put key b's name where the n-th occurrence of key a is.
    RenameKey(usize, usize, usize),
}

fn edit() -> impl Strategy<Value = Edit> {
    prop_oneof![
        4 => (any::<usize>(), 0..NUMBERS.len()).prop_map(|(n, v)| Edit::Number(n, v)),
        1 => any::<usize>().prop_map(Edit::DeleteLine),
        1 => any::<usize>().prop_map(Edit::RepeatLine),
        1 => any::<usize>().prop_map(Edit::Truncate),
        1 => (0..KEYS.len(), 0..KEYS.len(), any::<usize>())
            .prop_map(|(a, b, n)| Edit::RenameKey(a, b, n)),
    ]
}

/// Byte ranges of the number literals of `text`: a digit, or a sign before one, that does
/// not continue a name (so the 1 of "x1" is not one), up to the end of the number.
fn number_literals(text: &str) -> Vec<std::ops::Range<usize>> {
    let bytes = text.as_bytes();
    let mut ranges = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        let starts_number = bytes[i].is_ascii_digit()
            || (matches!(bytes[i], b'-' | b'+')
                && bytes.get(i + 1).is_some_and(u8::is_ascii_digit));
        let after_name =
            i > 0 && (bytes[i - 1].is_ascii_alphanumeric() || matches!(bytes[i - 1], b'_' | b'.'));
        if starts_number && !after_name {
            let start = i;
            i += 1;
            while i < bytes.len()
                && (bytes[i].is_ascii_digit()
                    || matches!(bytes[i], b'.' | b'e' | b'E' | b'_')
                    || (matches!(bytes[i], b'-' | b'+') && matches!(bytes[i - 1], b'e' | b'E')))
            {
                i += 1;
            }
            ranges.push(start..i);
        } else {
            i += 1;
        }
    }
    ranges
}

fn apply(text: &str, edit: &Edit) -> String {
    match *edit {
        Edit::Number(n, value) => {
            let numbers = number_literals(text);
            if numbers.is_empty() {
                return text.to_string();
            }
            let range = numbers[n % numbers.len()].clone();
            format!(
                "{}{}{}",
                &text[..range.start],
                NUMBERS[value],
                &text[range.end..]
            )
        }
        Edit::DeleteLine(n) | Edit::RepeatLine(n) => {
            let mut lines: Vec<&str> = text.lines().collect();
            if lines.is_empty() {
                return text.to_string();
            }
            let k = n % lines.len();
            if matches!(edit, Edit::DeleteLine(_)) {
                lines.remove(k);
            } else {
                lines.insert(k, lines[k]);
            }
            lines.join("\n") + "\n"
        }
        Edit::Truncate(n) => {
            let mut cut = n % (text.len() + 1);
            while !text.is_char_boundary(cut) {
                cut -= 1;
            }
            text[..cut].to_string()
        }
        Edit::RenameKey(a, b, n) => {
            let pattern = format!("{} =", KEYS[a]);
            let found: Vec<usize> = text.match_indices(&pattern).map(|(i, _)| i).collect();
            if found.is_empty() {
                return text.to_string();
            }
            let at = found[n % found.len()];
            format!(
                "{}{} ={}",
                &text[..at],
                KEYS[b],
                &text[at + pattern.len()..]
            )
        }
    }
}

fn examples_directory() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples")
}

/// Build the edited scene; run it when it is a small implicit model. Returns what
/// happened, for the case's label.
fn check_scene(name: &str, text: &str) -> Result<&'static str, TestCaseError> {
    let path = examples_directory().join(name);
    let (scene, locator) = match parse_scene(text, &path) {
        Ok(parsed) => parsed,
        Err(error) => {
            let message = error.to_string();
            prop_assert!(
                message.contains(name),
                "the error does not name the file: {message}"
            );
            return Ok("refused when read");
        }
    };
    let model = match build_model(&scene, &locator, &mut MaterialLibrary::with_builtins()) {
        Ok(model) => model,
        Err(error) => {
            let message = error.to_string();
            prop_assert!(
                message.contains(name),
                "the error does not name the file: {message}"
            );
            return Ok("refused when built");
        }
    };
    let small_implicit = match &model.analysis {
        Analysis::Implicit(settings) => {
            settings.increments <= 40 && model.mesh.element_count() <= 200
        }
        Analysis::Explicit(_) => false,
    };
    if !small_implicit {
        return Ok("built");
    }
    let started = Instant::now();
    let outcome = model.run(&mut NoObserver);
    prop_assert!(
        started.elapsed() < Duration::from_secs(60),
        "a small implicit run took {:?}",
        started.elapsed()
    );
    match outcome {
        Ok(result) => {
            prop_assert!(
                result
                    .displacement()
                    .iter()
                    .all(|u| u.iter().all(|c| c.is_finite())),
                "a run ended with non-finite displacements"
            );
            Ok("run to the end")
        }
        Err(_) => Ok("refused or failed in the run"),
    }
}

#[test]
fn edited_scenes_are_refused_with_the_file_named_or_built_never_a_panic() {
    let cases = std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(160);
    let mut runner = TestRunner::new(ProptestConfig {
        cases,
        failure_persistence: None,
        ..ProptestConfig::default()
    });
    let outcomes = RefCell::new(BTreeMap::<&str, usize>::new());
    let strategy = (0..EXAMPLES.len(), proptest::collection::vec(edit(), 1..4));
    let result = runner.run(&strategy, |(example, edits)| {
        let name = EXAMPLES[example];
        let original = std::fs::read_to_string(examples_directory().join(name)).unwrap();
        let text = edits.iter().fold(original, |text, edit| apply(&text, edit));
        let what = check_scene(name, &text)?;
        *outcomes.borrow_mut().entry(what).or_default() += 1;
        Ok(())
    });
    let outcomes = outcomes.into_inner();
    println!("{cases} edited scenes: {outcomes:?}");
    if let Err(failure) = result {
        panic!("{failure}");
    }
    // The edits reach both sides: some scenes are refused, some still build.
    let refused = outcomes.get("refused when read").unwrap_or(&0)
        + outcomes.get("refused when built").unwrap_or(&0);
    assert!(refused > 0 && refused < cases as usize, "{outcomes:?}");
}

#[test]
fn the_edits_find_what_they_edit() {
    let text = "a = 1\nb = [-2.5e-3, 4]\nname_x1 = \"x1\"\n";
    let numbers: Vec<&str> = number_literals(text)
        .into_iter()
        .map(|r| &text[r])
        .collect();
    assert_eq!(numbers, ["1", "-2.5e-3", "4"]);
    assert_eq!(
        apply(text, &Edit::Number(1, 9)),
        "a = 1\nb = [nan, 4]\nname_x1 = \"x1\"\n"
    );
    assert_eq!(
        apply("name = 1\n", &Edit::RenameKey(0, 1, 0)),
        "model = 1\n"
    );
    assert_eq!(apply("a\nb\n", &Edit::RepeatLine(1)), "a\nb\nb\n");
    assert_eq!(apply("a\nb\n", &Edit::DeleteLine(0)), "b\n");
    assert_eq!(apply("abc", &Edit::Truncate(5)), "a");
}
