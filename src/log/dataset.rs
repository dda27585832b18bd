//! Many logs to one dataset: the logs a command line names (files, folders,
//! globs) and the partition of each log's signals, hive style
//! (`PATH/log=NAME/part-0.parquet`), which DuckDB
//! (`read_parquet('PATH/*/*.parquet', hive_partitioning = true)`), pyarrow
//! (`pyarrow.dataset.dataset(PATH, partitioning = "hive")`), Polars and
//! Spark (`spark.read.parquet(PATH)`) read as one table with a `log`
//! column. The layout is Apache Hive's partitioned table directories, the
//! one these readers discover by the `name=value` folder names.

use std::io;
use std::path::{Path, PathBuf};
use std::prelude::rust_2021::*;

/// The format of a dataset's parts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PartFormat {
    /// `part-0.csv`: the `--signals` CSV of each log.
    Csv,
    /// `part-0.parquet`: the `--signals` Parquet of each log.
    Parquet,
}

impl PartFormat {
    /// The parts' format a dataset folder's name says: Parquet for a name
    /// ending in `.parquet`, else CSV.
    pub fn of(root: &Path) -> Self {
        if crate::log::signals::is_parquet(root) {
            PartFormat::Parquet
        } else {
            PartFormat::Csv
        }
    }

    fn extension(self) -> &'static str {
        match self {
            PartFormat::Csv => "csv",
            PartFormat::Parquet => "parquet",
        }
    }
}

/// The logs that the command line's arguments name, in order: a file as
/// it is; a folder, its files (not its subfolders, nor hidden files) in
/// name order; a path whose last part holds `*` or `?` (and no such file
/// exists), the files of its folder that it matches, in name order (for a
/// shell that did not expand it, as Windows' do not). The second value
/// says whether a folder or a glob was among them: such logs are a
/// dataset even when only one matched. A folder or glob without a file,
/// a glob in a folder's name, or an unreadable folder, is an error.
pub fn logs(args: &[String]) -> Result<(Vec<String>, bool), String> {
    let mut files = Vec::new();
    let mut many = false;
    for arg in args {
        let path = Path::new(arg);
        let found = if path.is_dir() {
            files_of(path, |_| true)
        } else if !path.exists() && arg.contains(['*', '?']) {
            let pattern = path.file_name().map(|n| n.to_string_lossy().into_owned());
            let pattern = pattern.unwrap_or_default();
            let folder = match path.parent() {
                Some(p) if !p.as_os_str().is_empty() => p,
                _ => Path::new("."),
            };
            if folder.to_string_lossy().contains(['*', '?']) {
                return Err(format!("{arg}: a glob matches file names, not folders"));
            }
            files_of(folder, |name| matches(pattern.as_bytes(), name.as_bytes()))
        } else {
            files.push(arg.clone());
            continue;
        };
        let found = found.map_err(|e| format!("{arg}: {e}"))?;
        if found.is_empty() {
            return Err(format!("{arg}: no log there"));
        }
        many = true;
        files.extend(found);
    }
    Ok((files, many))
}

/// The files (not folders, not hidden) of `folder` whose name `keep`s, in
/// name order.
fn files_of(folder: &Path, keep: impl Fn(&str) -> bool) -> io::Result<Vec<String>> {
    let mut found = Vec::new();
    for entry in std::fs::read_dir(folder)? {
        let entry = entry?;
        let name = entry.file_name().to_string_lossy().into_owned();
        if name.starts_with('.') || !keep(&name) || !entry.path().is_file() {
            continue;
        }
        found.push(entry.path().display().to_string());
    }
    found.sort();
    Ok(found)
}

/// Whether `name` matches the glob `pattern`: `*` any run of bytes, `?`
/// one byte, any other byte itself. Iterative with one back-track point,
/// so time is bounded by the product of the lengths.
fn matches(pattern: &[u8], name: &[u8]) -> bool {
    let (mut p, mut n) = (0, 0);
    let mut star: Option<(usize, usize)> = None;
    while n < name.len() {
        match (pattern.get(p), name.get(n)) {
            (Some(b'*'), _) => {
                star = Some((p, n));
                p += 1;
            }
            (Some(&c), Some(&b)) if c == b'?' || c == b => {
                p += 1;
                n += 1;
            }
            _ => match star {
                Some((sp, sn)) => {
                    p = sp + 1;
                    n = sn + 1;
                    star = Some((sp, sn + 1));
                }
                None => return false,
            },
        }
    }
    pattern
        .get(p..)
        .unwrap_or_default()
        .iter()
        .all(|&c| c == b'*')
}

/// Each log's part under `root`, the `log=NAME` folders made: NAME is the
/// log's file name without its extension, and without `.gz` first for a
/// gzip-compressed log (`truck-017.log.gz` is `truck-017`, as
/// `truck-017.log`), with `/`, `\` and `=` made `_`; one per log; two logs
/// of one NAME are an error (a partition each is needed).
pub fn parts(root: &Path, files: &[String], format: PartFormat) -> Result<Vec<PathBuf>, String> {
    let fail = |why: String| format!("--signals {}: {why}", root.display());
    let mut names: Vec<String> = Vec::new();
    let mut parts = Vec::new();
    for f in files {
        let file = Path::new(f);
        let file = match file.extension() {
            Some(gz) if gz == "gz" => file.file_stem().map_or(file, Path::new),
            _ => file,
        };
        let name = file
            .file_stem()
            .map(|s| s.to_string_lossy().replace(['/', '\\', '='], "_"))
            .unwrap_or_default();
        if name.is_empty() || names.contains(&name) {
            return Err(fail(format!(
                "two logs named '{name}': a partition each is needed"
            )));
        }
        let folder = root.join(format!("log={name}"));
        std::fs::create_dir_all(&folder).map_err(|e| fail(e.to_string()))?;
        parts.push(folder.join(format!("part-0.{}", format.extension())));
        names.push(name);
    }
    Ok(parts)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn globs_match_as_a_shell_does() {
        assert!(matches(b"*.log", b"a.log"));
        assert!(matches(b"*.log", b".log"));
        assert!(!matches(b"*.log", b"a.log.gz"));
        assert!(matches(b"bus-?.log", b"bus-1.log"));
        assert!(!matches(b"bus-?.log", b"bus-10.log"));
        assert!(matches(b"*-*-*.blf", b"a-b-c.blf"));
        assert!(!matches(b"*-*-*.blf", b"a-b.blf"));
        assert!(matches(b"**", b""));
        assert!(!matches(b"a", b""));
        // Many stars over a long name end without blowing up.
        assert!(matches(&[b'*'; 40], b""));
        let long = vec![b'a'; 5000];
        assert!(!matches(b"*a*a*a*b", &long));
    }

    #[test]
    fn folders_and_globs_expand_to_their_logs_in_name_order() {
        let dir = std::env::temp_dir().join(format!("canopen-dataset-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(dir.join("sub")).unwrap();
        for name in ["b.log", "a.log", "c.blf", ".hidden.log"] {
            std::fs::write(dir.join(name), "x").unwrap();
        }
        let d = dir.display().to_string();
        let (all, many) = logs(std::slice::from_ref(&d)).unwrap();
        assert!(many);
        let names: Vec<_> = all.iter().map(|f| f.rsplit('/').next().unwrap()).collect();
        assert_eq!(names, ["a.log", "b.log", "c.blf"]);
        let (some, many) = logs(&[format!("{d}/*.log"), "plain.log".into()]).unwrap();
        assert!(many);
        assert_eq!(some.len(), 3);
        assert!(some[0].ends_with("/a.log") && some[1].ends_with("/b.log"));
        assert_eq!(some[2], "plain.log");
        assert_eq!(
            logs(&["plain.log".into()]).unwrap(),
            (vec!["plain.log".into()], false)
        );
        assert!(logs(&[format!("{d}/*.trc")])
            .unwrap_err()
            .contains("no log"));
        assert!(logs(&[format!("{d}/sub")]).unwrap_err().contains("no log"));
        assert!(logs(&[format!("{d}/*/a.log")]).is_err());

        let root = dir.join("fleet.parquet");
        assert_eq!(PartFormat::of(&root), PartFormat::Parquet);
        assert_eq!(PartFormat::of(&dir), PartFormat::Csv);
        let got = parts(&root, &some, PartFormat::Parquet).unwrap();
        assert_eq!(got[0], root.join("log=a/part-0.parquet"));
        assert_eq!(got[2], root.join("log=plain/part-0.parquet"));
        assert!(root.join("log=b").is_dir());
        let twice = parts(
            &root,
            &["x/a.log".into(), "y/a.blf".into()],
            PartFormat::Csv,
        );
        assert!(twice.unwrap_err().contains("two logs named 'a'"));
        // A gzip-compressed log is named by its log's file name.
        let gz = parts(
            &root,
            &["x/truck-1.log.gz".into(), "truck-2.pcapng.gz".into()],
            PartFormat::Csv,
        );
        assert_eq!(gz.unwrap()[0], root.join("log=truck-1/part-0.csv"));
        assert!(root.join("log=truck-2").is_dir());
        let same = parts(&root, &["a.log".into(), "a.log.gz".into()], PartFormat::Csv);
        assert!(same.unwrap_err().contains("two logs named 'a'"));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
