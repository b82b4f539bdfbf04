//! sssbake's analysis, for every door: a material's reflectance profile
//! tabulated and plotted, the Stam layer's responses per angle, and the
//! error-against-time report of the integrators with its plot and error
//! maps. The command line prints and writes what these return; a pipeline
//! calls them the same way.

pub mod angle_plot;
pub mod error_map;
pub mod plot;
pub mod profile_report;
pub mod report;
pub mod report_plot;
pub mod stam_contact_report;
pub mod stam_report;
