//! `musclefem picture` on a run of a small scene: the block pressed onto a rigid sphere
//! (examples/block_on_rigid_sphere.toml, coarsened), drawn at a time through its
//! result.pvd and rigid.pvd, and from a frame file; the PNG's size and colours; refusals.

mod support;

use std::path::Path;

use support::run::{example, musclefem, test_dir, text};

/// The example with 4 × 4 × 1 hex8 and 4 increments, a frame every 0.25 s.
fn run_small_scene(dir: &Path) {
    let scene = std::fs::read_to_string(example("block_on_rigid_sphere.toml")).unwrap();
    let small = scene
        .replacen("divisions = [8, 8, 2]", "divisions = [4, 4, 1]", 1)
        .replacen("increments = 10", "increments = 4", 1)
        .replacen("output_interval = 0.1", "output_interval = 0.25", 1)
        .replacen("divisions = 32", "divisions = 12", 1);
    assert_ne!(small, scene);
    std::fs::write(dir.join("scene.toml"), small).unwrap();
    let out = musclefem(dir, &["run", "scene.toml", "--out", "result"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
}

/// The PNG's width, height and RGB bytes.
fn decode(path: &Path) -> (u32, u32, Vec<u8>) {
    let decoder = png::Decoder::new(std::fs::File::open(path).unwrap());
    let mut reader = decoder.read_info().unwrap();
    let mut rgb = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut rgb).unwrap();
    assert_eq!(info.color_type, png::ColorType::Rgb);
    rgb.truncate(info.buffer_size());
    (info.width, info.height, rgb)
}

/// Number of distinct colours in an RGB image.
fn colours(rgb: &[u8]) -> usize {
    let mut seen: Vec<[u8; 3]> = rgb.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
    seen.sort_unstable();
    seen.dedup();
    seen.len()
}

#[test]
fn a_run_is_drawn_at_a_time_with_its_rigid_body() {
    let dir = test_dir("musclefem-picture", "run");
    run_small_scene(&dir);

    let out = musclefem(
        &dir,
        &[
            "picture",
            "--run",
            "result",
            "--time",
            "0.6",
            "--view",
            "0,-1,-0.3",
            "--up",
            "0,0,1",
            "--size",
            "640x480",
            "--out",
            "block.png",
        ],
    );
    let stdout = text(&out.stdout);
    assert!(out.status.success(), "{stdout}{}", text(&out.stderr));
    // 0.6 s is nearest the frame at 0.5 s; the sphere of the same frame is drawn.
    assert!(stdout.contains("frame_00002.vtu (t = 0.5 s)"), "{stdout}");
    assert!(stdout.contains("block 0: 16 hex8 cells"), "{stdout}");
    assert!(stdout.contains("rigid_00002.vtu"), "{stdout}");
    // 4 × 4 × 1 cells: 2 · 16 + 4 · 4 = 48 boundary quadrilaterals, two triangles each.
    assert!(
        stdout.contains("16 cells drawn by 96 boundary triangles"),
        "{stdout}"
    );
    let (width, height, rgb) = decode(&dir.join("block.png"));
    assert_eq!((width, height), (640, 480));
    assert!(colours(&rgb) > 50, "{} colours", colours(&rgb));
    // Grey (the sphere, lit) is there: r = g = b, neither white nor black.
    assert!(
        rgb.chunks_exact(3)
            .any(|c| c[0] == c[1] && c[1] == c[2] && (120..200).contains(&c[0])),
        "no grey"
    );

    // The same frame from its file, without the sphere, coloured by another array over a
    // given range; a second picture onto the first is refused without --force.
    let frame = "result/frames/frame_00002.vtu";
    let args = [
        "picture",
        "--frame",
        frame,
        "--field",
        "fiber_stretch",
        "--range",
        "0.9,1.1",
        "--out",
        "block.png",
    ];
    let refused = musclefem(&dir, &args);
    assert!(!refused.status.success());
    assert!(
        text(&refused.stderr).contains("--force"),
        "{}",
        text(&refused.stderr)
    );
    let out = musclefem(&dir, &[&args[..], &["--force"]].concat());
    let stdout = text(&out.stdout);
    assert!(out.status.success(), "{stdout}{}", text(&out.stderr));
    assert!(
        stdout.contains("(t = 0.5 s)") && !stdout.contains("rigid"),
        "{stdout}"
    );
    assert!(
        stdout.contains("colour range 0.900 to 1.100 (as given)"),
        "{stdout}"
    );
    let (width, height, _) = decode(&dir.join("block.png"));
    assert_eq!((width, height), (1200, 900));
}

#[test]
fn what_cannot_be_drawn_is_named() {
    let dir = test_dir("musclefem-picture", "refusals");
    run_small_scene(&dir);
    let frame = "result/frames/frame_00001.vtu";
    let cases: [(&[&str], &str); 5] = [
        (
            &["--frame", frame, "--field", "speed"],
            "no cell array 'speed'",
        ),
        (&["--frame", frame, "--block", "4"], "there is no block 4"),
        (&["--frame", frame, "--view", "upward"], "view 'upward'"),
        (&["--frame", frame, "--range", "5,1"], "LO must be below HI"),
        (&["--run", "nowhere", "--time", "1"], "result.pvd"),
    ];
    for (args, expected) in cases {
        let out = musclefem(&dir, &[&["picture"], args, &["--out", "p.png"]].concat());
        let stderr = text(&out.stderr);
        assert!(!out.status.success(), "{args:?}");
        assert!(stderr.contains(expected), "{args:?}: {stderr}");
    }
    assert!(!dir.join("p.png").exists());
}
