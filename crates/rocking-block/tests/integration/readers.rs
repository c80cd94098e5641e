//! The command line's file readers under random corruption: CSV batches of trials and shard
//! files (the restart reader is fuzzed with the library, `tests/public_api_fuzz.rs`). Every
//! input is accepted or refused with one line; none panics, and what is accepted is
//! consistent. 2,000 cases per reader (`PROPTEST_CASES` overrides).

use proptest::prelude::*;
use rocking_block::classes::parse_trials;
use rocking_block::cli::ShardFile;
use std::sync::OnceLock;

fn config() -> ProptestConfig {
    ProptestConfig {
        cases: std::env::var("PROPTEST_CASES")
            .ok()
            .and_then(|s| s.parse().ok())
            .unwrap_or(2000),
        failure_persistence: None,
        ..ProptestConfig::default()
    }
}

/// A valid shard file of Fig. 9 (two tables of 30 x 30 cells), written by the command line.
fn shard_text() -> &'static str {
    static TEXT: OnceLock<String> = OnceLock::new();
    TEXT.get_or_init(|| {
        let dir = std::env::temp_dir().join(format!("rb-readers-{}", std::process::id()));
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_rocking-block"))
            .args(["figure", "9", "--trials", "40", "--shard", "1/2", "--out"])
            .arg(&dir)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let text = std::fs::read_to_string(dir.join("fig9.shard-1-of-2.json")).unwrap();
        std::fs::remove_dir_all(&dir).ok();
        text
    })
}

fn field() -> impl Strategy<Value = String> {
    prop_oneof![
        (-10.0f64..10.0).prop_map(|x| x.to_string()),
        Just("NaN".to_string()),
        Just("inf".to_string()),
        Just(String::new()),
        Just("x".to_string()),
        Just("1e400".to_string()),
    ]
}

proptest! {
    #![proptest_config(config())]

    /// CSV batches: random headers, field counts and values.
    #[test]
    fn csv_batches(header in prop::collection::vec(
                       prop::sample::select(vec!["omega", "alpha", "beta", "phi0", "psi0", "x"]),
                       0..7),
                   rows in prop::collection::vec(prop::collection::vec(field(), 0..7), 0..5)) {
        let mut text = header.join(",");
        for r in &rows {
            text.push('\n');
            text.push_str(&r.join(","));
        }
        match parse_trials(&text) {
            Ok(parsed) => {
                prop_assert!(parsed.iter().flatten().all(|v| v.is_finite()));
                prop_assert!(parsed.len() <= rows.len());
            }
            Err(line) => prop_assert!(!line.contains('\n') && !line.is_empty()),
        }
    }

    /// Shard files: a byte changed, the text cut, or a number replaced.
    #[test]
    fn shard_files(at in 0usize..1_000_000, byte in any::<u8>(), cut in 0usize..1_000_000,
                   number in prop::sample::select(vec!["-1", "1e308", "18446744073709551615", "0", "3.5", "null"])) {
        let mut text = shard_text().to_string();
        let at = at % text.len();
        match cut % 3 {
            0 => {
                let mut bytes = text.into_bytes();
                bytes[at] = byte;
                text = String::from_utf8_lossy(&bytes).into_owned();
            }
            1 => {
                // The char boundary at or before `at` (`floor_char_boundary` needs Rust 1.91).
                let cut = (0..=at).rev().find(|&i| text.is_char_boundary(i)).unwrap_or(0);
                text.truncate(cut);
            }
            _ => {
                // Replace the number starting at or after `at`.
                if let Some(start) = text[at..].find(|c: char| c.is_ascii_digit()).map(|i| i + at) {
                    let end = text[start..]
                        .find(|c: char| !c.is_ascii_digit())
                        .map_or(text.len(), |i| i + start);
                    text.replace_range(start..end, number);
                }
            }
        }
        match ShardFile::parse(&text) {
            Ok(file) => {
                let (done, total) = file.progress();
                prop_assert!(done <= total);
                prop_assert!(file.counts.iter().all(|c| c.validate().is_ok()));
            }
            Err(line) => prop_assert!(!line.contains('\n') && !line.is_empty()),
        }
    }
}

#[test]
fn the_unchanged_shard_file_is_read() {
    let file = ShardFile::parse(shard_text()).unwrap();
    assert_eq!((file.figure, file.trials, file.shard), (9, 40, (1, 2)));
    assert!(file.is_complete());
}
