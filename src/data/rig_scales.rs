//! Where data meets the model: the `[rig]` table of a rig file to the model's dimensional
//! scales ([`Dimensional`], paper Sec. 2.1), the rig's values checked first. The model makes
//! the scales from plain numbers ([`GearSpec`]) and knows nothing of rig files.

use super::rig::Rig;
use crate::error::Result;
use crate::model::{Dimensional, GearSpec};

impl Rig {
    /// The rig's values the dimensional scales are made from (teeth, module, pressure angle,
    /// face width, backlash, and the stiffness and contact ratio if given).
    pub fn gear_spec(&self) -> GearSpec {
        GearSpec {
            pinion_teeth: self.pinion_teeth,
            gear_teeth: self.gear_teeth,
            module_mm: self.module_mm,
            pressure_angle_deg: self.pressure_angle_deg,
            face_width_mm: self.face_width_mm,
            backlash_mm: self.backlash_mm,
            mesh_stiffness_n_per_um: self.mesh_stiffness_n_per_um,
            contact_ratio: self.contact_ratio,
        }
    }

    /// The rig's scales ([`Dimensional::new`] of [`Rig::gear_spec`]), the rig validated first:
    /// bad values give [`crate::GearError::InvalidParameter`] naming the key.
    pub fn dimensional(&self) -> Result<Dimensional> {
        self.validate()?;
        Dimensional::new(&self.gear_spec())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::data::munro_rig;
    use crate::error::GearError;
    use crate::model::munro_spec;

    /// Munro's rig of the data and the model's Munro gears (tests) are the same gears.
    #[test]
    fn a_valid_rig_gives_the_scales_of_its_gears() {
        let mut rig = munro_rig();
        assert_eq!(rig.gear_spec(), munro_spec());
        assert_eq!(
            rig.dimensional().unwrap(),
            Dimensional::new(&munro_spec()).unwrap()
        );
        rig.mesh_stiffness_n_per_um = Some(250.0);
        rig.contact_ratio = Some(2.0);
        let g = rig.gear_spec();
        assert_eq!(
            (g.mesh_stiffness_n_per_um, g.contact_ratio),
            (Some(250.0), Some(2.0))
        );
        assert_eq!(rig.dimensional().unwrap(), Dimensional::new(&g).unwrap());
    }

    #[test]
    fn bad_rig_values_are_rejected() {
        type Edit = fn(&mut Rig);
        let cases: [(&str, Edit); 9] = [
            ("pinion_teeth", |r| r.pinion_teeth = 4),
            ("gear_teeth", |r| r.gear_teeth = 0),
            ("backlash_mm", |r| r.backlash_mm = 0.0),
            ("backlash_mm", |r| r.backlash_mm = f64::NAN),
            ("module_mm", |r| r.module_mm = -6.35),
            ("pressure_angle_deg", |r| r.pressure_angle_deg = 35.0),
            ("pressure_angle_deg", |r| r.pressure_angle_deg = 10.0),
            ("zeta", |r| r.zeta = Some(1.0)),
            ("face_width_mm", |r| r.face_width_mm = f64::INFINITY),
        ];
        for (key, edit) in cases {
            let mut rig = munro_rig();
            edit(&mut rig);
            match rig.dimensional() {
                Err(GearError::InvalidParameter { name, .. }) => assert_eq!(name, key),
                other => panic!("{key}: expected InvalidParameter, got {other:?}"),
            }
        }
    }
}
