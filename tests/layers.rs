//! The crate's layers (docs/layout.md): a module of the library imports only from the layers
//! above its own, its tests included, so that no module imports a higher one and no imports
//! form a circle. Every `crate::<module>` path outside comments in `src/` is checked.

use std::fs;
use std::path::{Path, PathBuf};

/// The layers, lowest first (docs/layout.md); a module imports only from lower layers.
const LAYERS: [&[&str]; 9] = [
    &["error"],
    &["numeric", "fast_math", "progress"],
    &["model"],
    &["sim", "data", "fit", "plot"],
    &["hb", "mesh", "digitize"],
    &["bifurcation", "study", "validate"],
    &["compare", "discover"],
    &["report"],
    &["reproduce", "method_study"],
];

fn layer_of(module: &str) -> Option<usize> {
    LAYERS.iter().position(|l| l.contains(&module))
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The modules named by `crate::<module>` in a line of code (comments left out).
fn crate_paths(line: &str) -> Vec<String> {
    let code = line.trim_start();
    if code.starts_with("//") {
        return Vec::new();
    }
    let mut out = Vec::new();
    let mut rest = code;
    while let Some(at) = rest.find("crate::") {
        let before = rest[..at].chars().last();
        rest = &rest[at + "crate::".len()..];
        if before.is_some_and(|c| c.is_alphanumeric() || c == '_') {
            continue;
        }
        let name: String = rest
            .chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect();
        out.push(name);
    }
    out
}

#[test]
fn lower_layers_never_import_higher_ones() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    files.sort();
    let mut wrong = Vec::new();
    for file in &files {
        let rel = file.strip_prefix(&src).unwrap();
        let first = rel
            .components()
            .next()
            .unwrap()
            .as_os_str()
            .to_string_lossy();
        let module = first.trim_end_matches(".rs").to_string();
        if module == "lib" || module == "main" || module == "cli" {
            continue;
        }
        let own = layer_of(&module)
            .unwrap_or_else(|| panic!("src/{module} is in no layer of tests/layers.rs"));
        let text = fs::read_to_string(file).unwrap();
        for (i, line) in text.lines().enumerate() {
            for used in crate_paths(line) {
                // `crate::GearError` and `crate::Result` are the error's, re-exported.
                let used = match used.as_str() {
                    "GearError" | "Result" => "error".to_string(),
                    _ => used,
                };
                if used == module {
                    continue;
                }
                let allowed = match layer_of(&used) {
                    Some(l) => l < own,
                    None => false,
                };
                if !allowed {
                    wrong.push(format!(
                        "src/{}:{}: {module} uses crate::{used}",
                        rel.display(),
                        i + 1
                    ));
                }
            }
        }
    }
    assert!(
        wrong.is_empty(),
        "imports against the layers:\n{}",
        wrong.join("\n")
    );
}

#[test]
fn crate_paths_are_read_from_code_only() {
    assert_eq!(
        crate_paths("use crate::model::{GearPair, Term};"),
        ["model"]
    );
    assert_eq!(
        crate_paths("    /// see [`crate::validate::Rng`]"),
        Vec::<String>::new()
    );
    assert_eq!(
        crate_paths("let x = crate::numeric::min_max(crate::sim::f());"),
        ["numeric", "sim"]
    );
    assert_eq!(crate_paths("use geardyn_crate::x;"), Vec::<String>::new());
}
