//! `remove_temporary_files` (its own test binary: it makes every later write of the process
//! fail, as it should for a program about to exit).

use delmesh_io::{remove_temporary_files, transaction, write_atomic, IoError};
use std::path::Path;

fn entries(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

#[test]
fn an_interrupted_run_leaves_no_temporary_file() {
    let dir = tempfile::tempdir().unwrap();
    let (a, b) = (dir.path().join("a.vtu"), dir.path().join("b.vtu"));
    std::fs::write(&a, "old a").unwrap();
    let write = |path: &Path, text: &str| {
        write_atomic(path, |w| {
            w.write_all(text.as_bytes()).map_err(|e| IoError::Io {
                file: path.to_path_buf(),
                source: e,
            })
        })
    };
    let result = transaction(|| {
        write(&a, "new a")?;
        write(&b, "new b")?;
        // Two files written, waiting for the commit: Ctrl-C comes.
        assert_eq!(entries(dir.path()).len(), 3, "{:?}", entries(dir.path()));
        assert_eq!(remove_temporary_files(), 2);
        assert_eq!(entries(dir.path()), vec!["a.vtu"]);
        // Nothing more can be written.
        let err = write(&b, "late").unwrap_err();
        assert!(err.to_string().contains("interrupted"), "{err}");
        Ok::<_, IoError>(())
    });
    // The commit finds its temporary files gone: an error, and the old file is untouched.
    assert!(result.is_err());
    assert_eq!(std::fs::read_to_string(&a).unwrap(), "old a");
    assert_eq!(entries(dir.path()), vec!["a.vtu"]);
}
