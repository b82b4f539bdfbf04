//! A material's reflectance profile: tabulated at radii, as a table, JSON
//! and a plot, with a Monte Carlo simulation and the empirical fit's error
//! beside it when asked.

use crate::plot::{Curve, render_svg};
use serde_json::{Value, json};
use sssbake::Error;
use sssbake::transport::texture_space::MAX_GAUSSIANS;
use sssbake_profile::models::empirical::{EmpiricalProfile, EmpiricalSettings, FitError};
use sssbake_profile::models::monte_carlo::{self, MonteCarlo};
use sssbake_profile::profile::default_radii;
use sssbake_profile::{Material, Model, Profile, Rgb, Tabulated, build_profile};

/// What a profile is asked for.
#[derive(Clone, Debug)]
pub struct ProfileRequest {
    /// The model (not `stam`, which answers per angle).
    pub model: Model,
    /// Radii, mm, increasing [default: 60 from the peak to d_max].
    pub radii: Option<Vec<f64>>,
    /// The fraction of the reflectance allowed beyond d_max.
    pub epsilon: f64,
    /// Gaussians in a fit.
    pub gaussians: usize,
    /// Whether to simulate the Monte Carlo reference beside the model.
    pub compare_montecarlo: bool,
    /// Photons per channel of the simulation.
    pub photons: u64,
    /// Its seed.
    pub seed: u64,
}

/// A material's profile at radii, with the simulation and the empirical
/// fit's error where they were asked for or made.
pub struct ProfileAnalysis {
    /// The material.
    pub material: Material,
    /// The model shown.
    pub model: Model,
    /// Its profile (the simulation's, tabulated, for `montecarlo`).
    pub profile: Box<dyn Profile>,
    /// Radii, mm.
    pub radii: Vec<f64>,
    /// The fraction of the reflectance allowed beyond d_max.
    pub epsilon: f64,
    /// The Monte Carlo reference, when simulated.
    pub simulation: Option<MonteCarlo>,
    /// The empirical model's fit, for its error.
    pub empirical: Option<EmpiricalProfile>,
}

/// The material a profile is asked of: a preset by name or a TOML file,
/// one of the two.
pub fn material(preset: Option<&str>, file: Option<&std::path::Path>) -> Result<Material, Error> {
    match (preset, file) {
        (Some(_), Some(_)) => Err(Error::field(
            "preset",
            "give a preset or a material file, not both",
        )),
        (Some(name), None) => sssbake_profile::presets::named(name).map_err(Error::input),
        (None, Some(path)) => Material::from_file(path).map_err(Error::from),
        (None, None) => Err(Error::field("preset", "give a preset or a material file")),
    }
}

impl ProfileRequest {
    /// Refuses a request no analysis can answer, naming the field.
    pub fn validate(&self) -> Result<(), Error> {
        if let Some(radii) = &self.radii {
            if radii.is_empty() {
                return Err(Error::field("radii", "give at least one radius in mm"));
            }
            if let Some(r) = radii.iter().find(|r| !(r.is_finite() && **r >= 0.0)) {
                return Err(Error::field(
                    "radii",
                    format!("{r} is not a finite, non-negative radius in mm"),
                ));
            }
            if radii.windows(2).any(|w| w[1] <= w[0]) {
                return Err(Error::field("radii", "radii must increase"));
            }
        }
        if !(self.epsilon > 0.0 && self.epsilon < 1.0) {
            return Err(Error::field(
                "epsilon",
                format!("{} must lie strictly between 0 and 1", self.epsilon),
            ));
        }
        if !(1..=MAX_GAUSSIANS).contains(&self.gaussians) {
            return Err(Error::field(
                "gaussians",
                format!("{} must be between 1 and {MAX_GAUSSIANS}", self.gaussians),
            ));
        }
        let simulates = self.compare_montecarlo || self.model == Model::MonteCarlo;
        if self.photons == 0 && simulates {
            return Err(Error::field(
                "photons",
                "the Monte Carlo reference needs at least one photon",
            ));
        }
        Ok(())
    }
}

/// Analyses `material` as `request` asks.
pub fn analyse(material: &Material, request: &ProfileRequest) -> Result<ProfileAnalysis, Error> {
    request.validate()?;
    let model = request.model;
    let needs_simulation = model == Model::MonteCarlo || request.compare_montecarlo;
    if needs_simulation && material.layers().is_none() {
        return Err(Error::input(format!(
            "material `{}` is a measured sum of Gaussians; it has no layers to simulate",
            material.name
        )));
    }

    let reference_model = if model == Model::MonteCarlo {
        Model::default_for(material)
    } else {
        model
    };
    // The empirical model's fit error is reported with its profile.
    let empirical = if model == Model::Empirical {
        let fitted = EmpiricalProfile::simulate(material, &EmpiricalSettings::default()).map_err(
            |reason| {
                Error::input(format!(
                    "material `{}`: model empirical: {reason}",
                    material.name
                ))
            },
        )?;
        Some(fitted)
    } else {
        None
    };
    let profile: Box<dyn Profile> = match &empirical {
        Some(fitted) => Box::new(fitted.clone()),
        None => build_profile(material, reference_model, request.gaussians).map_err(Error::from)?,
    };
    let radii = match &request.radii {
        Some(r) => r.clone(),
        None => default_radii(profile.as_ref(), request.epsilon),
    };
    let simulation = needs_simulation.then(|| {
        let settings = monte_carlo::Settings::new(
            request.photons,
            request.seed,
            monte_carlo::edges_around(&radii),
        );
        monte_carlo::simulate(material.layers().unwrap_or_default(), &settings)
    });

    let shown: Box<dyn Profile> = match (&simulation, model) {
        (Some(mc), Model::MonteCarlo) => Box::new(tabulate_simulation(mc, &radii)),
        _ => profile,
    };
    Ok(ProfileAnalysis {
        material: material.clone(),
        model,
        profile: shown,
        radii,
        epsilon: request.epsilon,
        simulation,
        empirical,
    })
}

impl ProfileAnalysis {
    /// The table or JSON of the profile itself.
    pub fn report(&self) -> ProfileReport<'_> {
        ProfileReport {
            material: &self.material,
            model: self.model,
            profile: self.profile.as_ref(),
            radii: &self.radii,
            epsilon: self.epsilon,
        }
    }

    /// Everything as one JSON object: the profile, the fit's error, the
    /// simulation (at the top for `montecarlo`, under `montecarlo` beside
    /// another model).
    pub fn json(&self) -> Value {
        let mut value = self.report().json();
        if let (Some(fitted), Value::Object(fields)) = (&self.empirical, &mut value) {
            fields.insert("fit_error".into(), fit_error_json(fitted));
        }
        if let Some(mc) = &self.simulation {
            let key = (self.model != Model::MonteCarlo).then_some("montecarlo");
            add_simulation(&mut value, mc, key);
        }
        value
    }

    /// Everything as text for people.
    pub fn text(&self) -> String {
        let mut text = self.report().table();
        if let Some(fitted) = &self.empirical {
            text += &fit_error_summary(fitted);
        }
        if let Some(mc) = &self.simulation {
            text += &simulation_summary(mc);
        }
        text
    }

    /// The plot as SVG.
    pub fn svg(&self) -> String {
        let simulated = self.model == Model::MonteCarlo;
        let simulation = self.simulation.as_ref();
        plot(
            &self.report(),
            simulation.filter(|_| !simulated),
            simulation.filter(|_| simulated),
        )
    }
}

/// The simulation's bins as a profile (for d_max and plotting).
pub fn tabulate_simulation(mc: &MonteCarlo, radii: &[f64]) -> Tabulated {
    let positive: Vec<usize> = (0..radii.len()).filter(|&i| radii[i] > 0.0).collect();
    Tabulated::new(
        "montecarlo",
        positive.iter().map(|&i| radii[i]).collect(),
        positive.iter().map(|&i| mc.reflectance[i]).collect(),
        positive.iter().map(|&i| mc.transmittance[i]).collect(),
        mc.total_reflectance,
        mc.total_transmittance,
    )
}

/// A material's profile at `radii`, as a table or JSON.
pub struct ProfileReport<'a> {
    /// The material.
    pub material: &'a Material,
    /// The model shown.
    pub model: Model,
    /// Its profile (or the simulation's, tabulated).
    pub profile: &'a dyn Profile,
    /// Radii, mm.
    pub radii: &'a [f64],
    /// The energy fraction left beyond d_max.
    pub epsilon: f64,
}

impl ProfileReport<'_> {
    /// R(r) at each radius, 1/mm².
    pub fn reflectance(&self) -> Vec<Rgb> {
        self.radii
            .iter()
            .map(|&r| self.profile.reflectance(r))
            .collect()
    }

    /// As JSON: radii, R and T, totals, ballistic parts, d_max.
    pub fn json(&self) -> Value {
        json!({
            "material": self.material.name,
            "model": self.model.name(),
            "radii_mm": self.radii,
            "reflectance": self.reflectance(),
            "transmittance": self.radii.iter().map(|&r| self.profile.transmittance(r)).collect::<Vec<_>>(),
            "total_reflectance": self.profile.total_reflectance(),
            "total_transmittance": self.profile.total_transmittance(),
            "ballistic_reflectance": self.profile.ballistic_reflectance(),
            "ballistic_transmittance": self.profile.ballistic_transmittance(),
            "d_max_mm": self.profile.d_max(self.epsilon),
            "epsilon": self.epsilon,
        })
    }

    /// As a table for people.
    pub fn table(&self) -> String {
        let rgb = |v: Rgb| format!("{:>12.6} {:>12.6} {:>12.6}", v[0], v[1], v[2]);
        let mut text = format!(
            "material {}, model {}\n",
            self.material.name,
            self.model.name()
        );
        text += &format!(
            "total reflectance    {}\n",
            rgb(self.profile.total_reflectance())
        );
        text += &format!(
            "total transmittance  {}\n",
            rgb(self.profile.total_transmittance())
        );
        text += &format!(
            "d_max (eps {:.0e}) mm {}\n",
            self.epsilon,
            rgb(self.profile.d_max(self.epsilon))
        );
        text += &format!(
            "{:>12} {:>12} {:>12} {:>12}   (R in 1/mm²)\n",
            "r [mm]", "R red", "R green", "R blue"
        );
        for (r, v) in self.radii.iter().zip(self.reflectance()) {
            text += &format!(
                "{r:>12.5} {:>12.5e} {:>12.5e} {:>12.5e}\n",
                v[0], v[1], v[2]
            );
        }
        text
    }
}

/// The simulation's bins and totals added to `value`, under `key` or at its top.
pub fn add_simulation(value: &mut Value, mc: &MonteCarlo, key: Option<&str>) {
    let fields = json!({
        "reflectance": mc.reflectance,
        "reflectance_stderr": mc.reflectance_stderr,
        "transmittance": mc.transmittance,
        "transmittance_stderr": mc.transmittance_stderr,
        "bin_edges_mm": mc.edges_mm,
        "total_reflectance": mc.total_reflectance,
        "total_reflectance_stderr": mc.total_reflectance_stderr,
        "total_transmittance": mc.total_transmittance,
        "total_transmittance_stderr": mc.total_transmittance_stderr,
        "unscattered_reflectance": mc.unscattered_reflectance,
        "unscattered_transmittance": mc.unscattered_transmittance,
        "specular_reflectance": mc.specular_reflectance,
        "truncated_weight": mc.truncated,
        "photons": mc.photons,
        "interactions": mc.interactions,
    });
    let (Value::Object(target), Value::Object(fields)) = (value, fields) else {
        return;
    };
    match key {
        Some(key) => {
            target.insert(key.to_string(), Value::Object(fields));
        }
        None => target.extend(fields),
    }
}

/// The empirical fit's error per channel, as JSON (see [`FitError`]).
pub fn fit_error_json(fitted: &EmpiricalProfile) -> Value {
    let errors = fitted.fit_error();
    let per_channel = |f: fn(&FitError) -> f64| errors.iter().map(f).collect::<Vec<f64>>();
    json!({
        "mean_rms": per_channel(|e| e.mean_rms),
        "mean_relative_rms": per_channel(|e| e.mean_relative_rms),
        "mean_noise_rms": per_channel(|e| e.mean_noise_rms),
    })
}

/// The empirical fit's error per channel, in a line.
pub fn fit_error_summary(fitted: &EmpiricalProfile) -> String {
    let errors = fitted.fit_error();
    let row = |f: fn(&FitError) -> f64| {
        errors
            .iter()
            .map(|e| format!("{:.3e}", f(e)))
            .collect::<Vec<_>>()
            .join(" ")
    };
    format!(
        "Empirical fit within 10 mean free paths, per channel: RMS {} /(mfp² sr) \
         (simulation noise {}), RMS over peak {}\n",
        row(|e| e.mean_rms),
        row(|e| e.mean_noise_rms),
        row(|e| e.mean_relative_rms),
    )
}

/// The simulation's totals with their standard errors, in a line.
pub fn simulation_summary(mc: &MonteCarlo) -> String {
    let rgb = |v: Rgb, e: Rgb| {
        format!(
            "{:.5}±{:.5} {:.5}±{:.5} {:.5}±{:.5}",
            v[0], e[0], v[1], e[1], v[2], e[2]
        )
    };
    format!(
        "Monte Carlo ({} photons per channel): total reflectance {}, total transmittance {}\n",
        mc.photons,
        rgb(mc.total_reflectance, mc.total_reflectance_stderr),
        rgb(mc.total_transmittance, mc.total_transmittance_stderr),
    )
}

/// The profile's plot as SVG: R(r) per channel, with the simulation's bins
/// beside it (`overlay`) or as the profile itself with its error bars
/// (`simulated`).
pub fn plot(
    report: &ProfileReport,
    overlay: Option<&MonteCarlo>,
    simulated: Option<&MonteCarlo>,
) -> String {
    let mut curves: Vec<Curve> = (0..3)
        .map(|c| Curve {
            channel: c,
            label: report.model.name().to_string(),
            points: report
                .radii
                .iter()
                .map(|&r| (r, report.profile.reflectance(r)[c]))
                .collect(),
            errors: simulated.map(|mc| mc.reflectance_stderr.iter().map(|e| e[c]).collect()),
            markers: simulated.is_some(),
        })
        .collect();
    if let Some(mc) = overlay {
        curves.extend((0..3).map(|c| {
            Curve {
                channel: c,
                label: "Monte Carlo".into(),
                points: report
                    .radii
                    .iter()
                    .zip(&mc.reflectance)
                    .map(|(&r, v)| (r, v[c]))
                    .collect(),
                errors: Some(mc.reflectance_stderr.iter().map(|e| e[c]).collect()),
                markers: true,
            }
        }));
    }
    let title = format!("{} — {}", report.material.name, report.model.name());
    render_svg(&title, &curves)
}
