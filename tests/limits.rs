//! Plausibility limits (issue 17 item 4): the ISO 76 static load rating computed from the
//! geometry, against the published catalogue ratings of the bearings the presets describe.

use raceway::geometry::{Bearing, Race};
use raceway::limits::{peak_contact, StaticRating};

#[test]
fn static_rating_matches_the_catalogue_of_the_preset_bearings() {
    // SKF 6205 and 6203 (the CWRU data set's bearings): C0 = 7.8 kN and 4.75 kN.
    for (preset, catalogue) in [("cwru-6205-de", 7800.0), ("cwru-6203-fe", 4750.0)] {
        let r = StaticRating::of(&Bearing::load(preset).unwrap());
        assert!(
            (r.c0 / catalogue - 1.0).abs() < 0.03,
            "{preset}: {} N",
            r.c0
        );
        assert_eq!((r.x0, r.y0), (0.6, 0.5));
    }
}

#[test]
fn peak_contact_finds_the_most_stressed_contact() {
    let b = Bearing::load("niu2014-table1").unwrap();
    let qi = [100.0, 2000.0, 50.0];
    let qo = [120.0, 1900.0, 3000.0];
    let (p, j, race, q) = peak_contact(&b, &qi, &qo);
    let pi = b.hertz(Race::Inner).peak_pressure(2000.0);
    let po = b.hertz(Race::Outer).peak_pressure(3000.0);
    assert_eq!(p, pi.max(po));
    assert_eq!(
        (j, race, q),
        if pi > po {
            (1, Race::Inner, 2000.0)
        } else {
            (2, Race::Outer, 3000.0)
        }
    );
}
