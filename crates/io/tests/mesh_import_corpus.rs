//! The fuzz seed corpus (fuzz/corpus/) through the readers, and a random-mutation loop
//! over it: every input must give a mesh or an error, never a panic.
//!
//! `MUSCLEFEM_MUTATIONS=N cargo test --release -p musclefem-io --test mesh_import_corpus`
//! runs N mutations per seed instead of the default few hundred.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};

use musclefem_io::mesh_import::{parse_abaqus, parse_gmsh};

fn corpus(target: &str) -> Vec<(PathBuf, String)> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fuzz/corpus")
        .join(target);
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    files
        .into_iter()
        .filter_map(|p| {
            String::from_utf8(std::fs::read(&p).unwrap())
                .ok()
                .map(|t| (p, t))
        })
        .collect()
}

type Parser = fn(&str) -> bool;

fn abaqus(text: &str) -> bool {
    parse_abaqus(text, "corpus.inp").is_ok()
}

fn gmsh(text: &str) -> bool {
    parse_gmsh(text, "corpus.msh").is_ok()
}

#[test]
fn every_seed_parses() {
    for (target, parse) in [("read_abaqus", abaqus as Parser), ("read_gmsh", gmsh)] {
        let seeds = corpus(target);
        assert!(seeds.len() >= 2, "{target}");
        for (path, text) in seeds {
            assert!(parse(&text), "{}", path.display());
        }
    }
}

/// xorshift64*: deterministic, no dependency.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

/// Tokens that reach the readers' corner cases.
const TOKENS: [&str; 24] = [
    ",",
    "*",
    "**",
    "\n",
    "$",
    "nan",
    "inf",
    "-1",
    "0",
    "99999999999999999999",
    "1e308",
    "GENERATE",
    "*NODE",
    "*ELEMENT, TYPE=C3D10",
    "*NSET, NSET=A",
    "*SURFACE, NAME=S",
    "S7",
    "*INSTANCE, NAME=I, PART=P",
    "*END PART",
    "$EndNodes",
    "$Elements",
    "4.1 0 8",
    " ",
    "\"",
];

fn mutate(text: &str, rng: &mut Rng) -> String {
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    for _ in 0..1 + rng.below(3) {
        let n = lines.len();
        let i = rng.below(n);
        match rng.below(6) {
            0 if n > 1 => {
                lines.remove(i);
            }
            1 => {
                let line = lines.get(i).cloned().unwrap_or_default();
                lines.insert(rng.below(n + 1), line);
            }
            2 => {
                // Replace one whitespace/comma-separated field by a token.
                if let Some(line) = lines.get_mut(i) {
                    let mut fields: Vec<String> = line.split(',').map(str::to_string).collect();
                    let f = rng.below(fields.len());
                    fields[f] = TOKENS[rng.below(TOKENS.len())].to_string();
                    *line = fields.join(",");
                }
            }
            3 => {
                if let Some(line) = lines.get_mut(i) {
                    let cut = rng.below(line.len() + 1);
                    if line.is_char_boundary(cut) {
                        line.truncate(cut);
                    }
                }
            }
            4 => lines.insert(
                rng.below(n + 1),
                TOKENS[rng.below(TOKENS.len())].to_string(),
            ),
            _ => {
                if let Some(line) = lines.get_mut(i) {
                    let at = rng.below(line.len() + 1);
                    if line.is_char_boundary(at) {
                        line.insert_str(at, TOKENS[rng.below(TOKENS.len())]);
                    }
                }
            }
        }
    }
    lines.join("\n")
}

/// Runs `per_seed` mutations of every seed; returns (runs, accepted) or panics with the
/// input that made a reader panic.
fn mutation_loop(per_seed: usize) -> (usize, usize) {
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
    let (mut runs, mut accepted) = (0, 0);
    for (target, parse) in [("read_abaqus", abaqus as Parser), ("read_gmsh", gmsh)] {
        for (_, seed) in corpus(target) {
            let mut text = seed.clone();
            for k in 0..per_seed {
                // Mostly mutate the last mutant (deeper changes), sometimes restart.
                if k % 8 == 0 {
                    text = seed.clone();
                }
                text = mutate(&text, &mut rng);
                match catch_unwind(AssertUnwindSafe(|| parse(&text))) {
                    Ok(ok) => accepted += usize::from(ok),
                    Err(_) => panic!("{target} panicked on:\n---\n{text}\n---"),
                }
                runs += 1;
            }
        }
    }
    (runs, accepted)
}

#[test]
fn mutated_seeds_never_panic() {
    let per_seed = std::env::var("MUSCLEFEM_MUTATIONS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(300);
    let (runs, accepted) = mutation_loop(per_seed);
    eprintln!("{runs} mutated inputs, {accepted} still valid meshes");
    // Some mutations keep the file valid (e.g. a duplicated comment), most do not.
    assert!(accepted > 0 && accepted < runs, "{accepted} of {runs}");
}
