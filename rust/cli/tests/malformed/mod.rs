//! The malformed-input corpus: each case is a folder of files, written by
//! the test, that a bake must refuse. A case names the file the message
//! must name and words that say what is wrong.

pub mod files;
pub mod gltf;
pub mod quad;

/// One malformed input.
pub struct Case {
    /// Unique, for the case's folder and messages.
    pub name: String,
    /// Files written into the case's input folder (name, bytes).
    pub files: Vec<(String, Vec<u8>)>,
    /// The bake's arguments after `bake`; one starting with `@` is a file
    /// of the input folder.
    pub args: Vec<String>,
    /// The input file the message must name.
    pub blame: String,
    /// Words the message must contain, saying what is wrong.
    pub words: Vec<String>,
}

impl Case {
    /// A case over `files`, run as `bake @scene extra…`.
    pub fn new(
        name: &str,
        files: Vec<(&str, Vec<u8>)>,
        scene: &str,
        extra: &[&str],
        blame: &str,
        words: &[&str],
    ) -> Self {
        Case {
            name: name.to_string(),
            files: files.into_iter().map(|(n, b)| (n.to_string(), b)).collect(),
            args: std::iter::once(format!("@{scene}"))
                .chain(extra.iter().map(|a| a.to_string()))
                .collect(),
            blame: blame.to_string(),
            words: words.iter().map(|w| w.to_string()).collect(),
        }
    }
}

/// Every case of the corpus.
pub fn all() -> Vec<Case> {
    let mut cases = gltf::cases();
    cases.extend(files::cases());
    cases
}
