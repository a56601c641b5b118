use nalgebra::Vector3;

use super::*;
use crate::frames::tests::wenchang_frame as frame;
use crate::frames::WGS84_EARTH_RATE_RAD_S;

const ORBIT_M: [f64; 3] = [150.0e3, 520.0e3, -80.0e3];

fn evaluate(model: FieldModel, time_s: f64, position: &Vector3<f64>) -> FieldRemainder {
    let mut field = FieldRemainder::EMPTY;
    field.configure(model).unwrap();
    for _ in 0..model.frames_per_evaluation() {
        field.advance(&frame(), time_s, position).unwrap();
    }
    field
}

/// The work-item count is what the cursor walks: one evaluation completes in exactly
/// `frames_per_evaluation` frames, for every model and slice size.
#[test]
fn an_evaluation_takes_the_counted_frames() {
    for (degree, order) in [(2, 1), (2, 2), (4, 0), (4, 4), (8, 3), (12, 12)] {
        for terms_per_frame in [1, 3, 4, 7] {
            let model = FieldModel {
                degree,
                order,
                terms_per_frame,
            };
            let mut field = FieldRemainder::EMPTY;
            field.configure(model).unwrap();
            let frames = model.frames_per_evaluation();
            let position = Vector3::from(ORBIT_M);
            for _ in 0..frames - 1 {
                field.advance(&frame(), 10.0, &position).unwrap();
            }
            assert_eq!(field.evaluations(), 0, "{model:?}");
            field.advance(&frame(), 10.0, &position).unwrap();
            assert_eq!(field.evaluations(), 1, "{model:?}");
        }
    }
    // 12 x 12 at the default slice: 50 frames, 0.1 s at 500 Hz.
    let full = FieldModel {
        degree: 12,
        order: 12,
        terms_per_frame: DEFAULT_TERMS_PER_FRAME,
    };
    assert_eq!(full.work_items(), 200);
    assert_eq!(full.frames_per_evaluation(), 50);
    assert_eq!(FieldModel::J2_ONLY.frames_per_evaluation(), 2);
}

/// Zonal terms do not depend on longitude, so Earth rotation about the axis leaves their
/// launch-frame value at a fixed inertial point unchanged only when the axis is the launch
/// frame's spin axis: checked as the zonal field's component along the Earth axis being the
/// same a sidereal fraction later, while a tesseral field's changes.
#[test]
fn zonal_terms_ignore_earth_rotation_and_tesseral_terms_do_not() {
    let position = Vector3::from(ORBIT_M);
    let quarter_day_s = 0.25 * 2.0 * core::f64::consts::PI / WGS84_EARTH_RATE_RAD_S;
    let zonal = FieldModel {
        degree: 6,
        order: 0,
        terms_per_frame: 5,
    };
    let early = *evaluate(zonal, 0.0, &position).acceleration_launch_mps2();
    let late = *evaluate(zonal, quarter_day_s, &position).acceleration_launch_mps2();
    println!("zonal: {early:?} {late:?}");
    assert!((early - late).norm() < 1e-12 * early.norm());
    assert!(early.norm() > 1e-6);
    let tesseral = FieldModel {
        degree: 6,
        order: 6,
        terms_per_frame: 5,
    };
    let early = *evaluate(tesseral, 0.0, &position).acceleration_launch_mps2();
    let late = *evaluate(tesseral, quarter_day_s, &position).acceleration_launch_mps2();
    assert!((early - late).norm() > 1e-2 * early.norm());
}

/// The omitted RMS falls as the model grows, and J3 dominates what a J2-only model omits:
/// at 500 km, `(GM/r²)(a/r)³ √((n+1)(2n+1)) |C̄_30|` alone is 7.5e-5 m/s².
#[test]
fn the_omitted_field_shrinks_with_the_model() {
    let position = Vector3::from(ORBIT_M);
    let mut previous = f64::INFINITY;
    for (degree, order) in [(2, 1), (4, 0), (4, 4), (8, 8), (12, 12)] {
        let model = FieldModel {
            degree,
            order,
            terms_per_frame: 8,
        };
        let rms = evaluate(model, 0.0, &position).omitted_rms_mps2();
        println!("{degree} x {order}: omitted RMS {rms:e} m/s^2");
        assert!(rms < previous && rms > 0.0);
        previous = rms;
    }
    assert!(previous < 3.0e-5);
    let j2_as_harmonics = FieldModel {
        degree: 2,
        order: 1,
        terms_per_frame: 8,
    };
    let rms = evaluate(j2_as_harmonics, 0.0, &position).omitted_rms_mps2();
    assert!(rms > 7.5e-5 && rms < 1.0e-3, "{rms}");
}

/// Bad models are refused with `self` unchanged; a non-finite node drops the evaluation and
/// keeps the held value; point mass + J2 does nothing.
#[test]
fn bad_input_is_refused_and_the_held_value_kept() {
    let mut field = evaluate(
        FieldModel {
            degree: 4,
            order: 4,
            terms_per_frame: 100,
        },
        0.0,
        &Vector3::from(ORBIT_M),
    );
    let held = *field.acceleration_launch_mps2();
    let before = field.clone();
    for bad in [
        FieldModel {
            degree: 13,
            order: 0,
            terms_per_frame: 1,
        },
        FieldModel {
            degree: 1,
            order: 0,
            terms_per_frame: 1,
        },
        FieldModel {
            degree: 4,
            order: 5,
            terms_per_frame: 1,
        },
        FieldModel {
            degree: 4,
            order: 4,
            terms_per_frame: 0,
        },
    ] {
        assert_eq!(field.configure(bad), Err(NavError::InvalidConfiguration));
        assert_eq!(field, before);
    }
    let nan = Vector3::new(f64::NAN, 0.0, 0.0);
    assert_eq!(
        field.advance(&frame(), 1.0, &nan),
        Err(NavError::NonFiniteInput)
    );
    assert_eq!(*field.acceleration_launch_mps2(), held);
    assert_eq!(
        field.advance(&frame(), f64::INFINITY, &Vector3::from(ORBIT_M)),
        Err(NavError::NonFiniteInput)
    );
    let centre = *frame().earth_centre_launch_m();
    assert!(field.advance(&frame(), 2.0, &centre).is_err());
    assert_eq!(*field.acceleration_launch_mps2(), held);
    // Point mass + J2 alone: nothing added, the omitted RMS evaluated every second.
    let mut j2 = FieldRemainder::EMPTY;
    j2.configure(FieldModel::J2_ONLY).unwrap();
    for frame_index in 0..1000 {
        let time_s = 600.0 + f64::from(frame_index) * 0.002;
        j2.advance(&frame(), time_s, &Vector3::from(ORBIT_M))
            .unwrap();
    }
    assert_eq!(j2.evaluations(), 2);
    assert_eq!(*j2.acceleration_launch_mps2(), Vector3::zeros());
    assert!(j2.omitted_rms_mps2() > 1.0e-4);
}
