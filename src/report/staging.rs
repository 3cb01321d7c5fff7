//! Write a whole output folder or file atomically: build it beside its destination, then rename.

use crate::error::{GearError, Result};
use std::path::{Path, PathBuf};

/// An output folder under construction; `commit` moves it to its destination.
pub struct Staged {
    tmp: PathBuf,
    dest: PathBuf,
}

impl Staged {
    /// Start a staged folder for `dest` (created next to it, so the final rename is atomic).
    pub fn new(dest: &Path) -> Result<Self> {
        let parent = dest
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        std::fs::create_dir_all(parent).map_err(GearError::io(parent))?;
        let name = dest.file_name().and_then(|n| n.to_str()).unwrap_or("out");
        let tmp = parent.join(format!(".{name}.tmp-{}", std::process::id()));
        if tmp.exists() {
            std::fs::remove_dir_all(&tmp).map_err(GearError::io(&tmp))?;
        }
        std::fs::create_dir_all(&tmp).map_err(GearError::io(&tmp))?;
        Ok(Staged {
            tmp,
            dest: dest.to_path_buf(),
        })
    }

    /// Path inside the staged folder.
    pub fn path(&self, name: &str) -> PathBuf {
        self.tmp.join(name)
    }

    /// Write a text file into the staged folder.
    pub fn write(&self, name: &str, text: &str) -> Result<()> {
        let p = self.path(name);
        std::fs::write(&p, text).map_err(GearError::io(&p))
    }

    /// Replace the destination with the staged folder.
    pub fn commit(self) -> Result<PathBuf> {
        if self.dest.exists() {
            std::fs::remove_dir_all(&self.dest).map_err(GearError::io(&self.dest))?;
        }
        std::fs::rename(&self.tmp, &self.dest).map_err(GearError::io(&self.dest))?;
        Ok(self.dest.clone())
    }
}

impl Drop for Staged {
    fn drop(&mut self) {
        // Abandoned (error path): remove the partial folder.
        let _ = std::fs::remove_dir_all(&self.tmp);
    }
}

/// Write a single file atomically (temporary file in the same folder, then rename).
pub fn write_file_atomic(path: &Path, text: &str) -> Result<()> {
    let parent = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    std::fs::create_dir_all(parent).map_err(GearError::io(parent))?;
    let tmp = parent.join(format!(
        ".{}.tmp-{}",
        path.file_name().and_then(|n| n.to_str()).unwrap_or("out"),
        std::process::id()
    ));
    std::fs::write(&tmp, text).map_err(GearError::io(&tmp))?;
    std::fs::rename(&tmp, path).map_err(GearError::io(path))
}

/// Finish a report: write the page (HTML and Markdown) into the staged folder, move the folder
/// into place, then write the fitted-parameter JSON; returns the files written.
pub fn finish_report(
    stage: Staged,
    page: super::html::Page,
    title: &str,
    json_path: &Path,
    json: &serde_json::Value,
) -> Result<Vec<PathBuf>> {
    let (html, md) = page.finish(title);
    stage.write("index.html", &html)?;
    stage.write("report.md", &md)?;
    let text = serde_json::to_string_pretty(json)
        .map_err(|e| GearError::Numerical(format!("JSON: {e}")))?;
    let dest = stage.commit()?;
    write_file_atomic(json_path, &text)?;
    Ok(vec![
        json_path.to_path_buf(),
        dest.join("index.html"),
        dest.join("report.md"),
    ])
}
