//! `--excitation geometry` (issue 24): the STE harmonics and the mesh stiffness k(t) at the load
//! from the gear geometry of rig.toml and a tip relief, by the tooth-contact model of `geardyn
//! mesh` (docs/mesh-geometry.md), instead of one STE amplitude and a constant stiffness. Also
//! the relief options that `geardyn mesh` shares.

use super::limits::{real, whole};
use clap::{Args as ClapArgs, ValueEnum};
use geardyn::data::{load_profile_table, locate_rig_key, ProfilePoints};
use geardyn::mesh::ReliefShape;
use geardyn::validate::StiffnessChoice;
use geardyn::GearError;
use std::path::{Path, PathBuf};

/// An error of the tooth-contact model of the rig file `rig`: located at the rig.toml key (or
/// the profile table's line) it names, which says all; otherwise `what` and the rig file as its
/// context.
pub fn geometry_error(rig: &Path, what: &str, e: GearError) -> anyhow::Error {
    match locate_rig_key(rig, e) {
        e @ GearError::Data { .. } => e.into(),
        e => anyhow::Error::new(e).context(format!("{what} {}", rig.display())),
    }
}

/// A tip relief: its depth (given, or sized by Harris's rule for a load), length and shape.
#[derive(ClapArgs, Debug, Clone)]
pub struct ReliefArgs {
    /// Tip relief depth in µm on both gears (0: none), in [0, 1000].
    #[arg(long, allow_hyphen_values = true, value_parser = real(0.0, 1000.0, false),
          conflicts_with = "tip_relief_design_load_n")]
    pub tip_relief_um: Option<f64>,
    /// Size the tip relief depth for minimum STE peak-to-peak at this load (Harris's rule), N,
    /// in (0, 1e8].
    #[arg(long, allow_hyphen_values = true, value_parser = real(0.0, 1e8, true))]
    pub tip_relief_design_load_n: Option<f64>,
    /// Relief length along the line of action, mm, in (0, 1000] (default: Harris's long
    /// relief, the double-contact stretch (eps_alpha - 1) p_b).
    #[arg(long, allow_hyphen_values = true, value_parser = real(0.0, 1000.0, true))]
    pub relief_length_mm: Option<f64>,
    /// Relief shape.
    #[arg(long, value_enum)]
    pub relief_shape: Option<Shape>,
    /// Profile modification of each flank point by point, a CSV table `gear,diameter_mm,
    /// relief_um` (a measured deviation or a drawn modification; docs/data-format.md), added to
    /// the tip relief (--tip-relief-um 0 for the table alone).
    #[arg(long, value_name = "FILE")]
    pub profile_table: Option<PathBuf>,
}

/// Relief shape on the command line (`mesh`, `validate munro`, `--excitation geometry`).
#[derive(ValueEnum, Debug, Clone, Copy, PartialEq, Eq)]
pub enum Shape {
    Linear,
    Parabolic,
}

impl Shape {
    /// The library's shape.
    pub fn relief_shape(self) -> ReliefShape {
        match self {
            Shape::Linear => ReliefShape::Linear,
            Shape::Parabolic => ReliefShape::Parabolic,
        }
    }
}

impl ReliefArgs {
    /// The relief's shape (linear unless given).
    pub fn shape(&self) -> ReliefShape {
        self.relief_shape.unwrap_or(Shape::Linear).relief_shape()
    }

    /// The points of --profile-table (none without it).
    pub fn profile(&self) -> anyhow::Result<ProfilePoints> {
        Ok(match &self.profile_table {
            Some(path) => load_profile_table(path)?,
            None => ProfilePoints::default(),
        })
    }

    /// The relief options given, for the message that refuses them without a geometry.
    fn given(&self) -> Option<&'static str> {
        [
            (self.tip_relief_um.is_some(), "--tip-relief-um"),
            (
                self.tip_relief_design_load_n.is_some(),
                "--tip-relief-design-load-n",
            ),
            (self.relief_length_mm.is_some(), "--relief-length-mm"),
            (self.relief_shape.is_some(), "--relief-shape"),
            (self.profile_table.is_some(), "--profile-table"),
        ]
        .into_iter()
        .find_map(|(on, flag)| on.then_some(flag))
    }
}

/// Where the model's excitation comes from.
#[derive(ClapArgs, Debug, Clone)]
pub struct ExcitationArgs {
    /// Excitation. rig: one STE amplitude (--ste-um or rig.toml [ste]) and a constant mesh
    /// stiffness, the paper's eq. 5. geometry (with --rig): the STE harmonics and the loaded
    /// mesh stiffness k(t) of the tooth-contact model at --load-n, from rig.toml's gears and a
    /// tip relief (default: sized for minimum STE at the design load), as `geardyn mesh`
    /// computes them; --omega-n-hz is then the natural frequency at the design load.
    #[arg(long, value_enum, default_value_t = Excitation::Rig)]
    pub excitation: Excitation,
    #[command(flatten)]
    pub relief: ReliefArgs,
    /// With --excitation geometry: STE (and stiffness) harmonics of the mesh frequency in the
    /// model, 1 to 5.
    #[arg(long, default_value_t = 5, allow_hyphen_values = true, value_parser = whole(1..=5))]
    pub ste_harmonics: usize,
    /// With --excitation geometry: the mesh stiffness. geometry: the loaded k_h(F) and k(t) of
    /// the tooth-contact model; constant: k = 1 and k_h from rig.toml (or ISO 6336-1).
    #[arg(long, value_enum, default_value_t = Stiffness::Geometry)]
    pub mesh_stiffness: Stiffness,
}

#[derive(ValueEnum, Debug, Clone, Copy, PartialEq, Eq)]
pub enum Excitation {
    Rig,
    Geometry,
}

/// Mesh stiffness of a model excited by the geometry, on the command line (`validate munro`,
/// `--excitation geometry`).
#[derive(ValueEnum, Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stiffness {
    Constant,
    Geometry,
}

impl Stiffness {
    /// The library's choice.
    pub fn choice(self) -> StiffnessChoice {
        match self {
            Stiffness::Constant => StiffnessChoice::Constant,
            Stiffness::Geometry => StiffnessChoice::Geometry,
        }
    }
}

impl ExcitationArgs {
    /// Whether the geometry gives the excitation; geometry-only options without it are refused.
    pub fn uses_geometry(&self) -> anyhow::Result<bool> {
        if self.excitation == Excitation::Geometry {
            return Ok(true);
        }
        if let Some(flag) = self.relief.given() {
            anyhow::bail!("{flag} applies to --excitation geometry only");
        }
        Ok(false)
    }

    /// The stiffness choice of the library.
    pub fn stiffness(&self) -> StiffnessChoice {
        self.mesh_stiffness.choice()
    }
}
