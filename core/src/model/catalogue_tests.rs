//! The shipped catalogue, `robots/catalogue/parts.json`, against its sources: each part's key
//! numbers as the cited source gives them (a table written here from the source: MGDB's rows
//! at commit 215cacc, the data sheets and pages each belt cites), and the consistency of what
//! follows from them.

use super::catalogue::Catalogue;
use crate::testing;

/// The shipped catalogue.
fn shipped() -> Catalogue {
    let path = testing::repository().join("robots/catalogue/parts.json");
    Catalogue::load(&path).unwrap()
}

/// Whether `value` is `cited`, to the source's own digits.
fn agrees(value: Option<f64>, cited: f64) -> bool {
    value.is_some_and(|v| (v - cited).abs() <= 1e-12 * cited.abs())
}

/// Each motor's numbers as its MGDB row gives them: name, the row's key, then k_t (N m/A),
/// R (ohm), mass (kg), rotor inertia (kg m^2), no-load speed (rad/s), I_nom (A) and the largest
/// intermittent torque (N m; NaN where the row has none, `Inf`).
const MOTORS: [(&str, &str, [f64; 7]); 6] = [
    (
        "Allied Motion HT02501-A00",
        "AM_HT02501-A00",
        [0.159, 2.57, 0.38, 1.7e-5, 144.0, 2.779874213836478, 1.48],
    ),
    (
        "Allied Motion HT02502-A00",
        "AM_HT02502-A00",
        [0.189, 1.94, 0.56, 2.5e-5, 121.0, 3.3650793650793656, 2.33],
    ),
    (
        "Allied Motion HT02003-A00",
        "AM_HT02003-A00",
        [0.128, 1.19, 0.43, 1.8e-5, 175.0, 3.7890625, 2.54],
    ),
    (
        "Allied Motion HT02004-A00",
        "AM_HT02004-A00",
        [0.144, 1.3, 0.52, 2.4e-5, 153.0, 3.798611111111111, 2.67],
    ),
    (
        "Allied Motion HT03001-A00",
        "AM_HT03001-A00",
        [0.259, 2.25, 0.55, 6.1e-5, 88.0, 3.386100386100386, 2.76],
    ),
    (
        "maxon 597974",
        "MM_597974",
        [0.136, 0.28, 0.98, 0.00051, 217.817090648892, 10.5, f64::NAN],
    ),
];

/// Each gearbox's numbers as its MGDB row gives them: name, the row's key, then the ratio, mass
/// (kg), input inertia (kg m^2), efficiency, intermittent and continuous torque (N m).
const GEARBOXES: [(&str, &str, [f64; 6]); 5] = [
    (
        "Faulhaber 42GPT 3.6:1",
        "FH_42GPT_R3.6:1",
        [3.6, 0.31, 2e-6, 0.93, 3.3, 2.5],
    ),
    (
        "Faulhaber 42GPT 4.5:1",
        "FH_42GPT_R4.5:1",
        [4.5, 0.31, 2e-6, 0.93, 3.3, 2.5],
    ),
    (
        "Faulhaber 42GPT 6.6:1",
        "FH_42GPT_R6.6:1",
        [6.6, 0.31, 2e-6, 0.93, 3.3, 2.5],
    ),
    (
        "Faulhaber 42GPT 9:1",
        "FH_42GPT_R9:1",
        [9.0, 0.31, 1.33e-6, 0.93, 3.3, 2.5],
    ),
    (
        "maxon GPX 42 UP 3.9:1",
        "MM_GPX42UPKLSL03D9CPLW",
        [3.94736842105263, 0.4, 2.53e-6, 0.96, 7.0, 4.5],
    ),
];

#[test]
fn shipped_motors_agree_with_their_cited_rows() {
    let catalogue = shipped();
    assert_eq!(catalogue.motors.len(), MOTORS.len());
    for (name, row, cited) in MOTORS {
        let motor = catalogue
            .motor(name)
            .unwrap_or_else(|| panic!("{name} missing"));
        let cites = motor.source.contains("MGDB") && motor.source.contains(&format!("row {row}"));
        assert!(cites, "{name}: {}", motor.source);
        let shipped = [
            motor.torque_constant_nm_per_a,
            motor.resistance_ohm,
            motor.mass_kg,
            motor.rotor_inertia_kgm2,
            motor.no_load_speed_rad_s,
            motor.continuous_current_a,
        ];
        for (k, (value, cited)) in shipped.iter().zip(cited).enumerate() {
            assert!(
                agrees(*value, cited),
                "{name} number {k}: {value:?} != {cited}"
            );
        }
        match cited[6].is_nan() {
            true => assert_eq!(motor.peak_torque_nm, None, "{name}: no peak torque cited"),
            false => assert!(agrees(motor.peak_torque_nm, cited[6]), "{name} peak torque"),
        }
    }
}

#[test]
fn shipped_gearboxes_agree_with_their_cited_rows() {
    let catalogue = shipped();
    assert_eq!(catalogue.gearboxes.len(), GEARBOXES.len());
    for (name, row, cited) in GEARBOXES {
        let gearbox = (catalogue.gearboxes.iter())
            .find(|g| g.name == name)
            .unwrap_or_else(|| panic!("{name} missing"));
        assert!(gearbox.source.ends_with(&format!("row {row}")), "{name}");
        let shipped = [
            Some(gearbox.ratio),
            gearbox.mass_kg,
            gearbox.input_inertia_kgm2,
            gearbox.efficiency,
            gearbox.peak_torque_nm,
            gearbox.continuous_torque_nm,
        ];
        for (k, (value, cited)) in shipped.iter().zip(cited).enumerate() {
            assert!(
                agrees(*value, cited),
                "{name} number {k}: {value:?} != {cited}"
            );
        }
    }
}

/// The GT2 series: 2 mm pitch, 12 teeth at least (RepRap wiki), 6 mm wide (meta-matic's
/// guide), aluminium 6061-T6 of 2.70 g/cm^3 (its data sheet); a 20-tooth pulley of it weighs
/// rho pi w R^2 = 2.06 g.
#[test]
fn shipped_belts_agree_with_their_cited_pages() {
    let catalogue = shipped();
    let [belt] = catalogue.belts.as_slice() else {
        panic!("one belt series expected")
    };
    assert_eq!(
        (
            belt.pitch_mm,
            belt.width_mm,
            belt.density_kg_m3,
            belt.min_teeth
        ),
        (2.0, 6.0, 2700.0, 12)
    );
    for cited in ["RepRap wiki", "meta-matic", "6061-T6"] {
        assert!(belt.source.contains(cited), "{cited}");
    }
    let mass = belt.pulley_mass_kg(belt.pitch_radius_m(20));
    assert!((mass - 0.00206).abs() < 5e-6, "{mass}");
}

/// What follows from the numbers holds for every shipped part: k_t and R positive, the
/// continuous torque (given, or k_t I_nom) at most the peak torque, the no-load speed above
/// the largest speed nowhere, the gearboxes' continuous torque at most their peak.
#[test]
fn shipped_parts_are_consistent() {
    let catalogue = shipped();
    for motor in &catalogue.motors {
        let name = &motor.name;
        assert!(
            motor.torque_constant_nm_per_a.is_some_and(|k| k > 0.0),
            "{name}"
        );
        assert!(motor.resistance_ohm.is_some_and(|r| r > 0.0), "{name}");
        let continuous = motor.continuous_torque().unwrap();
        if let Some(peak) = motor.peak_torque_nm {
            assert!(continuous <= peak, "{name}: {continuous} > {peak}");
        }
        if let (Some(w0), Some(most)) = (motor.no_load_speed_rad_s, motor.max_speed_rad_s) {
            assert!(w0 <= most, "{name}");
        }
        assert!(motor.rotor_inertia_kgm2.is_some_and(|j| j > 0.0), "{name}");
    }
    for gearbox in &catalogue.gearboxes {
        let (peak, continuous) = (gearbox.peak_torque_nm, gearbox.continuous_torque_nm);
        assert!(continuous.unwrap() <= peak.unwrap(), "{}", gearbox.name);
        assert!(gearbox.ratio > 1.0, "{}", gearbox.name);
    }
}
