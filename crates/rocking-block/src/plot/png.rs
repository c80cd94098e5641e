//! PNG pictures: the SVG rendered by resvg with the bundled DejaVu Sans (regular and bold, in
//! `assets/fonts`), so that a PNG looks the same on every machine and needs no system fonts or
//! libraries.

use crate::error::{Error, Result};
use resvg::{tiny_skia, usvg};
use std::path::Path;
use std::sync::{Arc, OnceLock};

/// The fonts every PNG is drawn with; `sans-serif` (what the SVGs ask for) is DejaVu Sans.
fn fonts() -> Arc<usvg::fontdb::Database> {
    static FONTS: OnceLock<Arc<usvg::fontdb::Database>> = OnceLock::new();
    FONTS
        .get_or_init(|| {
            let mut db = usvg::fontdb::Database::new();
            db.load_font_data(include_bytes!("../../assets/fonts/DejaVuSans.ttf").to_vec());
            db.load_font_data(include_bytes!("../../assets/fonts/DejaVuSans-Bold.ttf").to_vec());
            db.set_sans_serif_family("DejaVu Sans");
            Arc::new(db)
        })
        .clone()
}

/// Renders `svg` (the text of an SVG picture) to PNG bytes, one pixel per SVG unit, on white.
///
/// # Errors
/// [`Error::Plot`] naming `path` (the PNG's file, for the message) if the SVG cannot be parsed
/// or is empty.
pub fn svg_to_png(svg: &str, path: &Path) -> Result<Vec<u8>> {
    let err = |message: String| Error::Plot {
        path: path.to_path_buf(),
        message,
    };
    let options = usvg::Options {
        font_family: "DejaVu Sans".into(),
        fontdb: fonts(),
        ..usvg::Options::default()
    };
    let tree = usvg::Tree::from_str(svg, &options).map_err(|e| err(e.to_string()))?;
    let size = tree.size().to_int_size();
    let mut pixmap = tiny_skia::Pixmap::new(size.width(), size.height())
        .ok_or_else(|| err(format!("empty picture ({size:?})")))?;
    pixmap.fill(tiny_skia::Color::WHITE);
    resvg::render(
        &tree,
        tiny_skia::Transform::identity(),
        &mut pixmap.as_mut(),
    );
    pixmap.encode_png().map_err(|e| err(e.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Text is drawn with the bundled font: a picture of a word has dark pixels where the word
    /// is and its size is the SVG's.
    #[test]
    fn text_renders_with_the_bundled_font() {
        let svg = r##"<svg width="120" height="40" viewBox="0 0 120 40" xmlns="http://www.w3.org/2000/svg">
<text x="5" y="30" font-family="sans-serif" font-size="24" fill="#000000">Fig. 2</text>
</svg>"##;
        let png = svg_to_png(svg, Path::new("t.png")).unwrap();
        let pixmap = tiny_skia::Pixmap::decode_png(&png).unwrap();
        assert_eq!((pixmap.width(), pixmap.height()), (120, 40));
        let dark = pixmap
            .pixels()
            .iter()
            .filter(|p| p.red() < 128 && p.green() < 128 && p.blue() < 128)
            .count();
        // "Fig. 2" at 24 px covers a few hundred pixels; without a font nothing is drawn.
        assert!(dark > 100, "{dark} dark pixels");
        let corner = pixmap.pixel(119, 0).unwrap();
        assert_eq!(
            (corner.red(), corner.green(), corner.blue()),
            (255, 255, 255)
        );
    }

    #[test]
    fn a_broken_svg_is_an_error_naming_the_file() {
        let e = svg_to_png("<svg", Path::new("x/fig.png")).unwrap_err();
        assert!(e.to_string().contains("x/fig.png"), "{e}");
    }
}
