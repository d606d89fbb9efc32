//! `shared_nodes`: two parts taking the two blocks of one mesh file (a belly and its
//! tendon, one hex each, meeting at a face) are joined when they share the file's nodes —
//! pulling the tendon's end loads the belly's held end with the opposite force — and
//! apart when each copies its block's nodes (the tendon then moves freely: no force).

mod support;

use support::run;

use run::{musclefem, test_dir, text};

use musclefem_io::csv::read_columns;

const DECK: &str = "\
*NODE
1, 0, 0, 0
2, 1, 0, 0
3, 2, 0, 0
4, 0, 1, 0
5, 1, 1, 0
6, 2, 1, 0
7, 0, 0, 1
8, 1, 0, 1
9, 2, 0, 1
10, 0, 1, 1
11, 1, 1, 1
12, 2, 1, 1
*ELEMENT, TYPE=C3D8, ELSET=BELLY
1, 1, 2, 5, 4, 7, 8, 11, 10
*ELEMENT, TYPE=C3D8, ELSET=TENDON
2, 2, 3, 6, 5, 8, 9, 12, 11
*NSET, NSET=start
1, 4, 7, 10
*NSET, NSET=end
3, 6, 9, 12
";

fn scene(shared: bool) -> String {
    let part = |name: &str, block: &str| {
        format!(
            "[[parts]]\nname = \"{name}\"\nmaterial = \"rubber\"\nelement = \"hex8-fbar\"\n\
             density = 1000.0\nmesh = {{ file = \"muscle.inp\", block = \"{block}\", \
             shared_nodes = {shared} }}\n\n"
        )
    };
    format!(
        "schema_version = 1\n\n[[materials]]\nname = \"rubber\"\nmodel = \"neo-hookean\"\n\n{}{}\
         [[rigid_ties]]\nname = \"held\"\npart = \"belly\"\nnodes = \"start\"\n\n\
         [[rigid_ties]]\nname = \"pull\"\npart = \"tendon\"\nnodes = \"end\"\n\
         translation = [0.1, 0.0, 0.0]\n\n[step]\nsolver = \"implicit\"\nduration = 1.0\n\n\
         [output]\nframes = false\n",
        part("belly", "BELLY"),
        part("tendon", "TENDON")
    )
}

#[test]
fn shared_nodes_join_the_blocks_of_one_file() {
    let dir = test_dir("musclefem-scene-shared-nodes", "join");
    std::fs::write(dir.join("muscle.inp"), DECK).unwrap();
    let last_pulls = |shared: bool| {
        let name = format!("shared_{shared}");
        std::fs::write(dir.join(format!("{name}.toml")), scene(shared)).unwrap();
        let out = musclefem(&dir, &["run", &format!("{name}.toml"), "--out", &name]);
        assert!(out.status.success(), "{}", text(&out.stderr));
        let (names, columns) = read_columns(&dir.join(name).join("history.csv")).unwrap();
        let last = |column: &str| {
            let c = &columns[names.iter().position(|n| n == column).unwrap()];
            c[c.len() - 1]
        };
        (last("reaction_held_x_n"), last("reaction_pull_x_n"))
    };
    let (held, pull) = last_pulls(true);
    assert!(pull > 100.0, "{pull} N");
    assert!((held + pull).abs() < 1e-9 * pull, "{held} + {pull}");
    // Apart, the tendon moves as a rigid body and the belly stays: no force at either end.
    let (held_apart, pull_apart) = last_pulls(false);
    assert!(held_apart.abs() < 1e-9 * pull, "{held_apart} N");
    assert!(pull_apart.abs() < 1e-9 * pull, "{pull_apart} N");
}
