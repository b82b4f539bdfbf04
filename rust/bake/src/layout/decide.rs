//! Whether an object keeps its UVs or is unwrapped, and the texels its
//! layout covers.

use super::{Layout, UvDecision};
use crate::error::{Error, InputError};
use crate::request::{BakeRequest, Lighting, UvPolicy};
use crate::scene::Scene;
use crate::surface::texels::rasterize;
use crate::surface::uv_analysis::analyse_uvs;

impl Layout {
    /// Decides whether object `index` of `scene` keeps its UVs, unwraps if
    /// not, and finds the texels its layout covers.
    pub fn new(
        scene: &Scene,
        index: usize,
        request: &BakeRequest,
    ) -> Result<(Layout, UvDecision), Error> {
        let original = &scene.objects[index].mesh;
        let object_error = |message: String| {
            Error::Input(InputError {
                file: Some(scene.source.clone()),
                object: Some(original.name.clone()),
                field: None,
                message,
            })
        };
        let resolution = request.resolution;
        let report = analyse_uvs(original, None, resolution);
        let verdict = report.verdict();
        let has_uvs = original.uvs.is_some();
        let (unwrap, reason, warning) = match request.uvs {
            UvPolicy::Keep if !has_uvs => {
                return Err(object_error("has no UVs to bake into".into()));
            }
            UvPolicy::Keep => (
                false,
                "its own UVs, as asked".to_string(),
                report
                    .problems()
                    .filter(|_| !report.usable())
                    .map(|problems| format!("baked into its UVs as they are: {problems}")),
            ),
            UvPolicy::Unwrap => (true, "unwrapping was asked for".to_string(), None),
            UvPolicy::Auto if report.usable() => {
                (false, "its own UVs are usable".to_string(), None)
            }
            UvPolicy::Auto => (true, format!("its UVs are not usable ({verdict})"), None),
        };
        if unwrap && matches!(request.lighting, Lighting::Irradiance(_)) {
            return Err(object_error(format!(
                "an irradiance image needs the object's own UVs, but {reason}"
            )));
        }
        let (mesh, source_vertex) = if unwrap {
            crate::surface::unwrap::unwrap_with_sources(original, resolution, request.margin)
                .map_err(|e| Error::from(e).in_file(scene.source.clone()))?
        } else {
            (original.clone(), Vec::new())
        };
        let uvs = mesh.uvs.clone().unwrap_or_default();
        let surfels = rasterize(&mesh, &uvs, resolution);
        if surfels.is_empty() {
            return Err(object_error(format!("covers no texel at {resolution}²")));
        }
        let layout = Layout {
            mesh,
            uvs,
            unwrapped: unwrap,
            source_vertex,
            surfels,
            relative_colour: Vec::new(),
            footprints: Default::default(),
        };
        let decision = UvDecision {
            verdict,
            unwrap,
            reason,
            warning,
        };
        Ok((layout, decision))
    }
}
