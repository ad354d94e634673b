//! `taut render` run as a designer would: pictures of the bundled cages on the software
//! rasteriser, and clear one-line errors for bad arguments.

use std::path::{Path, PathBuf};
use std::process::Output;

mod support;
use support::{assert_clean_failure, asset};

fn taut(args: &[&str]) -> Output {
    support::taut_in("cli-render", args)
}

fn scratch(test: &str) -> PathBuf {
    support::scratch_in("cli-render", test)
}

fn render(args: &[&str]) -> image::RgbaImage {
    let out = taut(args);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let path = args.iter().position(|&a| a == "-o").map(|k| args[k + 1]).unwrap();
    image::open(path).expect("a PNG was written").to_rgba8()
}

/// Fraction of pixels that are neither the background nor grey: coloured pixels.
fn coloured_fraction(image: &image::RgbaImage) -> f64 {
    let coloured = image.pixels().filter(|p| {
        let (r, g, b) = (p[0] as i32, p[1] as i32, p[2] as i32);
        (r - g).abs().max((g - b).abs()).max((r - b).abs()) > 40
    });
    coloured.count() as f64 / (image.width() * image.height()) as f64
}

#[test]
fn views_of_the_default_scene() {
    let dir = scratch("views");
    let out = |name: &str| dir.join(name).to_string_lossy().into_owned();
    let cage = asset("default.taut");
    let shaded = render(&["render", &cage, "-o", &out("shaded.png"), "--size", "320x200", "--software"]);
    assert_eq!(shaded.dimensions(), (320, 200));
    assert!(coloured_fraction(&shaded) < 0.01, "the shaded view is grey");
    let zebra =
        render(&["render", &cage, "-o", &out("zebra.png"), "--size", "320x200", "--view", "zebra", "--software"]);
    // Zebra: black and white pixels, many of both.
    let (black, white) = zebra.pixels().fold((0, 0), |(b, w), p| (b + (p[0] < 30) as u32, w + (p[0] > 225) as u32));
    assert!(black > 500 && white > 500, "black {black}, white {white}");
    let mean = render(&[
        "render",
        &cage,
        "-o",
        &out("mean.png"),
        "--size",
        "320x200",
        "--view",
        "mean",
        "--legend",
        "--software",
    ]);
    assert!(coloured_fraction(&mean) > 0.05, "the curvature view is not coloured");
    // The legend sits at the right: coloured pixels there that the shaded view lacks.
    let right = |img: &image::RgbaImage| {
        (img.width() - 40..img.width())
            .flat_map(|x| (0..img.height()).map(move |y| (x, y)))
            .filter(|&(x, y)| {
                let p = img.get_pixel(x, y);
                (p[0] as i32 - p[2] as i32).abs() > 60
            })
            .count()
    };
    assert!(right(&mean) > 200, "no colour bar at the right");
    // A fixed range changes the colours.
    let fixed = render(&[
        "render",
        &cage,
        "-o",
        &out("fixed.png"),
        "--size",
        "320x200",
        "--view",
        "mean",
        "--range",
        "-1,1",
        "--software",
    ]);
    assert!(coloured_fraction(&fixed) < coloured_fraction(&mean), "a wide fixed range should wash the colours out");
    // Overlays draw on top, and a different camera gives a different picture.
    let cage_on = render(&[
        "render",
        &cage,
        "-o",
        &out("cage.png"),
        "--size",
        "320x200",
        "--overlay",
        "cage,wire,curves",
        "--software",
    ]);
    let differing = shaded.pixels().zip(cage_on.pixels()).filter(|(a, b)| a != b).count();
    assert!(differing > 1000);
    let top = render(&["render", &cage, "-o", &out("top.png"), "--size", "320x200", "--camera", "0,90", "--software"]);
    assert!(shaded.pixels().zip(top.pixels()).filter(|(a, b)| a != b).count() > 1000);
}

#[test]
fn meshes_render_as_they_are_and_cages_when_asked() {
    let dir = scratch("meshes");
    let out = |name: &str| dir.join(name).to_string_lossy().into_owned();
    let cube = asset("cube.obj");
    let flat = render(&["render", &cube, "-o", &out("flat.png"), "--size", "200x200", "--view", "zebra", "--software"]);
    let smoothed = render(&[
        "render",
        &cube,
        "-o",
        &out("smooth.png"),
        "--size",
        "200x200",
        "--view",
        "zebra",
        "--levels",
        "3",
        "--software",
    ]);
    // The flat-faced cube has few stripes, the smoothed one many transitions.
    let transitions = |img: &image::RgbaImage| {
        let y = img.height() / 2;
        (1..img.width()).filter(|&x| (img.get_pixel(x, y)[0] > 128) != (img.get_pixel(x - 1, y)[0] > 128)).count()
    };
    assert!(transitions(&smoothed) > transitions(&flat), "{} vs {}", transitions(&smoothed), transitions(&flat));
}

#[test]
fn bad_arguments_fail_with_one_clear_line() {
    let dir = scratch("bad");
    let png = dir.join("x.png").to_string_lossy().into_owned();
    let cage = asset("default.taut");
    let cube = asset("cube.obj");
    assert_clean_failure(&taut(&["render", &cage, "-o", &png, "--view", "foo"]), "--view foo");
    assert_clean_failure(&taut(&["render", &cage, "-o", &png, "--size", "0x5"]), "--size 0x5");
    assert_clean_failure(&taut(&["render", &cage, "-o", &png, "--size", "big"]), "WIDTHxHEIGHT");
    assert_clean_failure(&taut(&["render", &cage, "-o", &png, "--overlay", "cage,bogus"]), "--overlay bogus");
    assert_clean_failure(&taut(&["render", &cage, "-o", &png, "--legend"]), "--legend goes with a colour view");
    assert_clean_failure(
        &taut(&["render", &cage, "-o", &png, "--view", "mean", "--range", "3,1"]),
        "MIN must be below MAX",
    );
    assert_clean_failure(&taut(&["render", &cage, "-o", &png, "--camera", "a,b"]), "not a number");
    assert_clean_failure(&taut(&["render", &cage, "-o", &png, "--camera", "10,20,-4"]), "distance must be positive");
    assert_clean_failure(&taut(&["render", &cube, "-o", &png, "--view", "r"]), "--view r");
    assert_clean_failure(&taut(&["render", &cube, "-o", &png, "--overlay", "cage"]), "needs a cage");
    assert_clean_failure(&taut(&["render", &cage, "-o", &dir.join("x.jpg").to_string_lossy()]), ".png");
    assert!(!Path::new(&png).exists());
}

#[test]
fn sections_draw_one_closed_curve_per_plane_through_a_closed_surface_with_combs() {
    let dir = scratch("sections");
    let cube = asset("cube.obj");
    let (plain, cut) = (dir.join("plain.png"), dir.join("cut.png"));
    let base = ["render", &cube, "--scheme", "catmull-clark", "--software"];
    let out = taut(&[&base[..], &["-o", &cut.to_string_lossy(), "--sections", "z:-40,0,40,60"]].concat());
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    // The limit surface of the ±50 cube reaches past ±40 but not 60: three loops, no fourth.
    assert!(stdout.contains("sections: 4 planes, 3 curves (3 closed)"), "{stdout}");
    let with = image::open(&cut).unwrap().to_rgba8();
    let without = render(&[&base[..], &["-o", &plain.to_string_lossy()]].concat());
    assert!(coloured_fraction(&with) > coloured_fraction(&without) + 0.002, "the sections and their combs are drawn");
    for (spec, said) in [("w:1", "'w' is not an axis"), ("z", "no ':'"), ("z:1,inf", "'inf' is not a finite number")] {
        let png = dir.join("bad.png");
        assert_clean_failure(&taut(&[&base[..], &["-o", &png.to_string_lossy(), "--sections", spec]].concat()), said);
        assert!(!png.exists());
    }
}

/// A document's reference images are drawn behind the surface, read only from beside the
/// document: one named outside its folder is told in a note and left out, and the picture is
/// still written.
#[test]
fn reference_images_are_drawn_and_those_outside_the_folder_refused() {
    use taut_core::document::{ReferenceImage, ReferencePlane};
    let dir = scratch("reference-images");
    let mut doc = taut_core::Document::load(Path::new(&asset("default.taut"))).unwrap();
    image::RgbaImage::from_pixel(8, 8, image::Rgba([0, 255, 0, 255])).save(dir.join("green.png")).unwrap();
    // A bright red picture outside: were it read, red would show.
    let outer = dir.parent().unwrap().join("reference-images-outside.png");
    image::RgbaImage::from_pixel(8, 8, image::Rgba([255, 0, 0, 255])).save(&outer).unwrap();
    doc.reference_images = vec![
        // Far larger than the model, facing the camera: it fills the picture's background.
        ReferenceImage::new("green.png", ReferencePlane::View, 1000.0),
        ReferenceImage {
            in_front: true,
            ..ReferenceImage::new("../reference-images-outside.png", ReferencePlane::View, 1000.0)
        },
    ];
    let input = dir.join("with-references.taut");
    doc.save(&input).unwrap();
    let output = dir.join("with-references.png");
    let (input, output) = (input.to_string_lossy().into_owned(), output.to_string_lossy().into_owned());
    let out = taut(&["render", &input, "-o", &output, "--size", "160x120", "--software"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        stdout.contains("note: reference image ../reference-images-outside.png points outside the document's folder"),
        "{stdout}"
    );
    let picture = image::open(&output).unwrap().to_rgba8();
    let corner = picture.get_pixel(2, 2);
    assert!(corner[1] > 240 && corner[0] < 20 && corner[2] < 20, "the green picture fills the corner: {corner:?}");
    let centre = picture.get_pixel(80, 60);
    assert!(centre[1] < 240 || centre[0] > 20, "the model hides the picture behind it: {centre:?}");
}
