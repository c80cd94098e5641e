//! Pictures from the command line: `--format svg|png|both` on figures, basins and merges,
//! `--png` on simulate, continue and curve; PNGs rendered with the bundled font at the SVG's
//! size; curves drawn with sub-pixel coordinates.

use crate::common;

use common::{RunOk, bin, fails, scratch};
use resvg::tiny_skia::Pixmap;
use std::path::Path;

/// `(width, height)` of an SVG written by rocking-block (from its root element).
fn svg_size(path: &Path) -> (u32, u32) {
    let text = std::fs::read_to_string(path).unwrap();
    let attr = |name: &str| -> u32 {
        let at = text.find(&format!("{name}=\"")).unwrap() + name.len() + 2;
        let end = at + text[at..].find('"').unwrap();
        text[at..end].parse().unwrap()
    };
    (attr("width"), attr("height"))
}

/// The decoded PNG at `path`.
fn png(path: &Path) -> Pixmap {
    Pixmap::decode_png(&std::fs::read(path).unwrap()).unwrap()
}

/// Pixels of `img` in the rows `rows` that are dark (text, axes) and that are saturated blue or
/// red (the curves of the two modes).
fn census(img: &Pixmap, rows: std::ops::Range<u32>) -> (usize, usize, usize) {
    let (mut dark, mut blue, mut red) = (0, 0, 0);
    for y in rows {
        for x in 0..img.width() {
            let p = img.pixel(x, y).unwrap();
            let (r, g, b) = (p.red(), p.green(), p.blue());
            dark += usize::from(r < 90 && g < 90 && b < 90);
            blue += usize::from(b > 150 && r < 90);
            red += usize::from(r > 180 && g < 90 && b < 90);
        }
    }
    (dark, blue, red)
}

/// `figure 2 --format both` writes the SVG and a PNG of the same size that shows the title (text
/// drawn with the bundled font) and both modes' curves; `--format png` writes no SVG and lists
/// what it wrote.
#[test]
fn figures_in_png_beside_or_instead_of_svg() {
    let dir = scratch("pictures-fig2");
    bin()
        .args(["figure", "2", "--format", "both", "--out"])
        .arg(&dir)
        .run_ok();
    let (svg, png_path) = (dir.join("fig2.svg"), dir.join("fig2.png"));
    let img = png(&png_path);
    assert_eq!((img.width(), img.height()), svg_size(&svg));
    // The title strip (top 30 px) holds text; the plots hold both colours.
    let (title_dark, _, _) = census(&img, 0..30);
    assert!(title_dark > 300, "{title_dark} dark pixels in the title");
    let (_, blue, red) = census(&img, 30..img.height());
    assert!(blue > 2000 && red > 2000, "blue {blue}, red {red}");

    let only = scratch("pictures-fig2-png");
    let out = bin()
        .args(["figure", "2", "--format", "png", "--json", "--out"])
        .arg(&only)
        .run_ok();
    let listed: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let names: Vec<&str> = listed["files"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f.as_str().unwrap().rsplit('/').next().unwrap())
        .collect();
    assert_eq!(names, ["fig2.json", "fig2.png"]);
    assert!(!only.join("fig2.svg").exists());
    let names: Vec<String> = std::fs::read_dir(&only)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names.len(), 2, "no temporary file left: {names:?}");
    assert_eq!(
        std::fs::read(&png_path).unwrap(),
        std::fs::read(only.join("fig2.png")).unwrap(),
        "the same picture whatever else is written"
    );
    std::fs::remove_dir_all(&dir).ok();
    std::fs::remove_dir_all(&only).ok();
}

/// The orbits of Fig. 2 are drawn with sub-pixel coordinates (whole pixels made them zig-zag):
/// most coordinates of the curves' paths are not whole numbers.
#[test]
fn curves_have_sub_pixel_coordinates() {
    let dir = scratch("pictures-fine");
    bin().args(["figure", "2", "--out"]).arg(&dir).run_ok();
    let text = std::fs::read_to_string(dir.join("fig2.svg")).unwrap();
    let mut coordinates = Vec::new();
    for path in text.split("<path d=\"").skip(1) {
        let d = &path[..path.find('"').unwrap()];
        coordinates.extend(
            d.split([' ', 'M', 'L'])
                .filter_map(|c| c.parse::<f64>().ok()),
        );
    }
    assert!(
        coordinates.len() > 2000,
        "{} coordinates",
        coordinates.len()
    );
    let whole = coordinates.iter().filter(|c| c.fract() == 0.0).count();
    assert!(
        whole * 10 < coordinates.len(),
        "{whole} of {} coordinates are whole pixels",
        coordinates.len()
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// `simulate`, `continue` and `curve` take `--png` beside `--svg` (the same picture); `basin`
/// and `merge` take `--format`.
#[test]
fn every_picture_command_writes_png() {
    let dir = scratch("pictures-commands");
    std::fs::create_dir_all(&dir).unwrap();
    bin()
        .args(["simulate", "--periods", "3", "--svg"])
        .arg(dir.join("sim.svg"))
        .arg("--png")
        .arg(dir.join("sim.png"))
        .run_ok();
    let img = png(&dir.join("sim.png"));
    assert_eq!((img.width(), img.height()), svg_size(&dir.join("sim.svg")));
    let run = dir.join("run.json");
    bin()
        .args(["continue", "--free", "alpha", "--max-points", "40", "--out"])
        .arg(&run)
        .arg("--png")
        .arg(dir.join("branch.png"))
        .run_ok();
    assert_eq!(png(&dir.join("branch.png")).width(), 1000);
    bin()
        .args(["basin", "--trials", "200", "--format", "png", "--out"])
        .arg(&dir)
        .run_ok();
    assert!(dir.join("basin.png").exists() && !dir.join("basin.svg").exists());
    for i in 0..2 {
        bin()
            .args([
                "basin",
                "--trials",
                "200",
                "--shard",
                &format!("{i}/2"),
                "--out",
            ])
            .arg(&dir)
            .run_ok();
    }
    let merged = dir.join("merged");
    bin()
        .arg("merge")
        .arg(dir.join("basin.shard-0-of-2.json"))
        .arg(dir.join("basin.shard-1-of-2.json"))
        .args(["--format", "both", "--out"])
        .arg(&merged)
        .run_ok();
    let img = png(&merged.join("basin.png"));
    assert_eq!(
        (img.width(), img.height()),
        svg_size(&merged.join("basin.svg"))
    );
    let out = bin()
        .args(["figure", "2", "--format", "gif", "--out"])
        .arg(&dir)
        .output()
        .unwrap();
    fails(&out, 2, "gif");
    std::fs::remove_dir_all(&dir).ok();
}
