//! The axially located inner ring through the FMU's parameters: `ring.axial` 0/1/2 and
//! `ring.axial_offset`, set in either order, edit the scene's mounting.

use ballbearing_fmu::variables::Config;
use raceway::{BearingFile, Mounting};

#[test]
fn ring_axial_parameters_edit_the_mounting() {
    let mut c = Config::default_for(&BearingFile::default_preset());
    assert_eq!(c.get("ring.axial"), Some(0.0));
    c.set("ring.axial", 2.0).unwrap();
    c.set("ring.axial_offset", 3e-6).unwrap();
    assert_eq!(c.scene.mounting.axial_offset, Some(3e-6));
    assert_eq!(c.get("ring.axial"), Some(2.0));
    c.set("ring.axial", 1.0).unwrap();
    assert_eq!(c.scene.mounting.axial_offset, None);
    assert_eq!(c.get("ring.axial_offset"), Some(3e-6));
    c.set("ring.axial", 0.0).unwrap();
    assert_eq!(c.scene.mounting, Mounting::default());
    assert!(c.set("ring.axial", 3.0).is_err());
}
