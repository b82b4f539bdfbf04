//! glTF URIs that name files: where they point and whether the file is there.

use std::path::{Path, PathBuf};

/// The file a relative glTF URI names, from `folder` (the glTF's own):
/// `%20`-style escapes decoded, as glTF URIs may carry them; a URI whose
/// escapes do not spell UTF-8 is taken as it is written.
pub(crate) fn local_path(folder: &Path, uri: &str) -> PathBuf {
    folder.join(percent_decode(uri))
}

/// `uri` with its escapes decoded (as written when they do not spell UTF-8).
pub(crate) fn percent_decode(uri: &str) -> String {
    urlencoding::decode(uri).map_or_else(|_| uri.to_string(), |d| d.into_owned())
}

/// Every buffer a file URI names is a file that can be opened: the `gltf`
/// crate's own message for a missing one is the system's ("No such file or
/// directory") without the name. Data URIs and the GLB chunk are checked
/// when they are decoded.
pub(crate) fn check_buffer_files(document: &gltf::Document, folder: &Path) -> Result<(), String> {
    for buffer in document.buffers() {
        let gltf::buffer::Source::Uri(uri) = buffer.source() else {
            continue;
        };
        if uri.starts_with("data:") {
            continue;
        }
        if uri.contains("://") {
            return Err(format!(
                "cannot load its buffers: buffer {} names \"{uri}\", which is not a local file \
                 (sssbake reads files beside the glTF and data: URIs, never the network)",
                buffer.index()
            ));
        }
        let path = local_path(folder, uri);
        if let Err(e) = std::fs::File::open(&path) {
            return Err(format!(
                "cannot load its buffers: buffer {} names \"{uri}\", but {} cannot be opened: {e}",
                buffer.index(),
                path.display()
            ));
        }
    }
    Ok(())
}
