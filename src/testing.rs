//! What the crate's own unit tests share (test builds only).

/// The configuration of an in-source property test: proptest's defaults,
/// with a failing case kept in `file` (under `tests/proptest-regressions/`)
/// so that the next run tries it first. proptest cannot find the source
/// file of a test inside the library, so each test names its own file.
pub(crate) fn proptest_config(file: &'static str) -> proptest::prelude::ProptestConfig {
    proptest::prelude::ProptestConfig {
        failure_persistence: Some(std::boxed::Box::new(
            proptest::test_runner::FileFailurePersistence::Direct(file),
        )),
        ..proptest::prelude::ProptestConfig::default()
    }
}
