//! Write a whole output folder or file atomically: build it beside its destination, then rename.

use crate::error::{GearError, Result};
use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard};

/// Staging folders and temporary files not yet moved into place: what an interrupted run must
/// remove so that it leaves no half-written output. Held while a commit renames, so that an
/// interrupt waits for the renames to finish.
static UNFINISHED: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

fn unfinished() -> MutexGuard<'static, Vec<PathBuf>> {
    UNFINISHED.lock().unwrap_or_else(|e| e.into_inner())
}

/// Record `path` (a folder or file being written) as unfinished until [`untrack_unfinished`].
pub fn track_unfinished(path: &Path) {
    unfinished().push(path.to_path_buf());
}

/// `path` is finished (moved into place, or removed).
pub fn untrack_unfinished(path: &Path) {
    unfinished().retain(|p| p != path);
}

/// For an interrupt (Ctrl-C) handler that ends the process next: remove every unfinished
/// staging folder and temporary file, after any commit under way has completed, and keep new
/// commits from starting.
pub fn remove_unfinished() {
    let mut list = unfinished();
    let paths: Vec<PathBuf> = list.drain(..).collect();
    // Worker threads may still be writing by path (and `create_dir_all` would make a removed
    // folder again): each path is first renamed aside and replaced by an empty file, in which
    // nothing can be created; the blockers go last, just before the process ends.
    let mut blockers = Vec::new();
    for p in &paths {
        let mut aside = p.clone().into_os_string();
        aside.push(".interrupted");
        let aside = PathBuf::from(aside);
        let target = if std::fs::rename(p, &aside).is_ok() {
            if std::fs::write(p, "").is_ok() {
                blockers.push(p.clone());
            }
            aside
        } else {
            p.clone()
        };
        let _ = std::fs::remove_dir_all(&target).or_else(|_| std::fs::remove_file(&target));
    }
    for b in blockers {
        let _ = std::fs::remove_file(b);
    }
    // The lock is kept: the process is about to end, and no commit may start before it does.
    std::mem::forget(list);
}

/// The file that marks a folder as one geardyn writes and replaces as a whole
/// ([`Staged::commit`]).
pub const OUTPUT_MARKER: &str = ".geardyn-output";

/// Whether `dest` may be replaced as a whole: it does not exist, is empty, or holds
/// [`OUTPUT_MARKER`] (an earlier run wrote it). A folder of the user's (a data set, notes) is
/// refused before any work is done, rather than deleted at the end.
pub fn check_replaceable(dest: &Path) -> Result<()> {
    if !dest.exists() || dest.file_name().is_none() {
        return Ok(());
    }
    if !dest.is_dir() {
        return Err(GearError::Unsupported(format!(
            "{}: is a file; name a folder for the output",
            dest.display()
        )));
    }
    if dest.join(OUTPUT_MARKER).exists() {
        return Ok(());
    }
    let mut names: Vec<String> = std::fs::read_dir(dest)
        .map_err(GearError::io(dest))?
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    if names.is_empty() {
        return Ok(());
    }
    names.sort();
    let shown = names.iter().take(3).cloned().collect::<Vec<_>>().join(", ");
    Err(GearError::Unsupported(format!(
        "{}: holds files geardyn did not write ({shown}{}); this output replaces its folder as \
         a whole, so name a new or empty folder",
        dest.display(),
        if names.len() > 3 { ", ..." } else { "" }
    )))
}

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
        track_unfinished(&tmp);
        // The error names the folder the user gave, not the internal staging name.
        std::fs::create_dir_all(&tmp).map_err(GearError::io(dest))?;
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

    /// The staged folder itself (for library writers that take a folder).
    pub fn dir(&self) -> &Path {
        &self.tmp
    }

    /// Where a path inside the staged folder will be once committed.
    pub fn final_path(&self, staged: &Path) -> PathBuf {
        match staged.strip_prefix(&self.tmp) {
            Ok(rel) => self.dest.join(rel),
            Err(_) => staged.to_path_buf(),
        }
    }

    /// Start a staged folder that will replace `dest` as a whole ([`Staged::commit`]); refused
    /// now when `dest` holds files geardyn did not write ([`check_replaceable`]).
    pub fn replacing(dest: &Path) -> Result<Self> {
        check_replaceable(dest)?;
        Staged::new(dest)
    }

    /// Replace the destination with the staged folder, marked with [`OUTPUT_MARKER`]; refused
    /// when the destination holds files geardyn did not write. A destination without a name of
    /// its own (`.`, `/`, `..`) is never removed: the staged files are merged into it instead.
    pub fn commit(self) -> Result<PathBuf> {
        if self.dest.file_name().is_none() {
            return self.commit_merge();
        }
        check_replaceable(&self.dest)?;
        self.write(
            OUTPUT_MARKER,
            "Written by geardyn. The next run that writes here replaces this folder as a whole.\n",
        )?;
        let mut list = unfinished();
        if self.dest.exists() {
            std::fs::remove_dir_all(&self.dest).map_err(GearError::io(&self.dest))?;
        }
        std::fs::rename(&self.tmp, &self.dest).map_err(GearError::io(&self.dest))?;
        list.retain(|p| p != &self.tmp);
        Ok(self.dest.clone())
    }
}

impl Staged {
    /// Move the staged files into the destination folder (created if needed), replacing files
    /// of the same name and leaving every other file there alone: for folders the user names
    /// (`--out DIR`), which may hold other things. Nothing reaches the destination before this
    /// is called, so a failed command leaves it as it was.
    pub fn commit_merge(self) -> Result<PathBuf> {
        let _list = unfinished();
        std::fs::create_dir_all(&self.dest).map_err(GearError::io(&self.dest))?;
        merge_into(&self.tmp, &self.dest)?;
        Ok(self.dest.clone())
    }
}

/// Move every entry of `from` into `to` (both folders), recursing into folders both have.
fn merge_into(from: &Path, to: &Path) -> Result<()> {
    let mut entries: Vec<_> = std::fs::read_dir(from)
        .map_err(GearError::io(from))?
        .collect::<std::io::Result<Vec<_>>>()
        .map_err(GearError::io(from))?;
    entries.sort_by_key(|e| e.file_name());
    for e in entries {
        let src = e.path();
        let dst = to.join(e.file_name());
        let src_is_dir = e.file_type().map_err(GearError::io(&src))?.is_dir();
        if src_is_dir && dst.is_dir() {
            merge_into(&src, &dst)?;
        } else {
            std::fs::rename(&src, &dst).map_err(GearError::io(&dst))?;
        }
    }
    Ok(())
}

impl Drop for Staged {
    fn drop(&mut self) {
        // Abandoned (error path), or emptied by a merge: remove what is left.
        let _ = std::fs::remove_dir_all(&self.tmp);
        untrack_unfinished(&self.tmp);
    }
}

/// Write a single file atomically (temporary file in the same folder, then rename).
pub fn write_file_atomic(path: &Path, text: &str) -> Result<()> {
    let tmp = staged_file(path, text)?;
    let mut list = unfinished();
    list.retain(|p| p != &tmp);
    std::fs::rename(&tmp, path).map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        GearError::io(path)(e)
    })
}

/// Write `text` to a temporary file beside `path` (creating the folder); returns its path.
fn staged_file(path: &Path, text: &str) -> Result<PathBuf> {
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
    track_unfinished(&tmp);
    std::fs::write(&tmp, text).map_err(|e| {
        untrack_unfinished(&tmp);
        GearError::io(&tmp)(e)
    })?;
    Ok(tmp)
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
    // The JSON is written beside its destination before the report folder moves into place, so
    // an unwritable fits folder leaves neither (only the two renames follow).
    let json_tmp = staged_file(json_path, &text)?;
    let dest = match stage.commit() {
        Ok(d) => d,
        Err(e) => {
            let _ = std::fs::remove_file(&json_tmp);
            untrack_unfinished(&json_tmp);
            return Err(e);
        }
    };
    let renamed = std::fs::rename(&json_tmp, json_path).map_err(GearError::io(json_path));
    untrack_unfinished(&json_tmp);
    renamed?;
    Ok(vec![
        json_path.to_path_buf(),
        dest.join("index.html"),
        dest.join("report.md"),
    ])
}
