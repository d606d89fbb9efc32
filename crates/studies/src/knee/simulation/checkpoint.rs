//! The knee's own part of a checkpoint: what its observer ([`Recorder`]) has gathered
//! when the solver's state is taken (every stress sample, the tendon's rows, the
//! plausibility samples, the explicit energy books, the stall window, the patella's
//! closest approach). A resumed squat reads it back into a recorder built for the same
//! model, so that its tables cover the whole squat; the pull the patella's pose follows
//! is the patella's own state, which the solver keeps in its part of the checkpoint
//! (`PoseFollower::save_state`): the run then computes what the uninterrupted one
//! computes, bit for bit (`musclefem_core::solver::checkpoint`).
//!
//! The patella's reports are stored too: beside a scene's run the recorder's patella is
//! its own copy of the scene's (see `Recorder::observes_patella`), which the solver's
//! checkpoint does not hold; reading them into the solver's own patella, which the solver
//! then restores too, changes nothing.
//!
//! Not stored: the solver's per-increment reports (`newton.csv`, `cuts.csv`), which a
//! resumed run has only from the checkpoint on.

use musclefem_core::solver::{CheckpointReader, CheckpointWriter, SolverError};

use super::patella::{TendonRow, TendonState};
use super::patella_clearance::PatellaApproach;
use super::peak_stress::{PeakLocation, StressSample};
use super::plausibility::PlausibilitySample;
use super::recorder::{Recorder, StallDetector};
use crate::knee::Quadriceps;
use crate::knee::anatomy::PatellaPose;

/// The recorder's and the patella's state, as bytes for the run's checkpoint.
pub(super) fn save_study(recorder: &Recorder) -> Vec<u8> {
    let mut out = CheckpointWriter::new();
    out.u64(recorder.samples.len() as u64);
    for sample in &recorder.samples {
        write_sample(&mut out, sample);
    }
    out.u64(recorder.tendon.len() as u64);
    for row in &recorder.tendon {
        out.f64(row.time);
        out.f64(row.measured_tension);
        write_tendon_state(&mut out, &row.applied);
    }
    out.u64(recorder.plausibility.len() as u64);
    for sample in &recorder.plausibility {
        write_plausibility(&mut out, sample);
    }
    out.f64(recorder.largest_energy);
    out.f64(recorder.energy_error);
    out.f64s(&recorder.stall.recent_times());
    match &recorder.patella_clearance.closest {
        None => out.u64(0),
        Some(approach) => {
            out.u64(1);
            out.f64(approach.distance);
            out.f64(approach.time);
            out.u64(muscle_index(approach.muscle));
            out.u64(approach.node as u64);
        }
    }
    recorder.patella.save_reports(&mut out);
    out.into_bytes()
}

/// Reads what [`save_study`] wrote into `recorder` (built for the same model).
pub(super) fn restore_study(recorder: &mut Recorder, bytes: &[u8]) -> Result<(), SolverError> {
    let mut input = CheckpointReader::new(bytes);
    let samples = input.index()?;
    recorder.samples = (0..samples)
        .map(|_| read_sample(&mut input))
        .collect::<Result<_, _>>()?;
    let rows = input.index()?;
    recorder.tendon = (0..rows)
        .map(|_| {
            Ok(TendonRow {
                time: input.f64()?,
                measured_tension: input.f64()?,
                applied: read_tendon_state(&mut input)?,
            })
        })
        .collect::<Result<_, SolverError>>()?;
    let samples = input.index()?;
    recorder.plausibility = (0..samples)
        .map(|_| read_plausibility(&mut input))
        .collect::<Result<_, _>>()?;
    recorder.largest_energy = input.f64()?;
    recorder.energy_error = input.f64()?;
    recorder.stall = StallDetector::with_recent_times(input.f64s()?);
    recorder.patella_clearance.closest = match input.u64()? {
        0 => None,
        _ => Some(PatellaApproach {
            distance: input.f64()?,
            time: input.f64()?,
            muscle: read_muscle(&mut input)?,
            node: input.index()?,
        }),
    };
    recorder.patella.restore_reports(&mut input)?;
    input.finish()
}

fn muscle_index(muscle: Quadriceps) -> u64 {
    Quadriceps::ALL
        .iter()
        .position(|&m| m == muscle)
        .unwrap_or(0) as u64
}

fn read_muscle(input: &mut CheckpointReader) -> Result<Quadriceps, SolverError> {
    let index = input.index()?;
    Quadriceps::ALL.get(index).copied().ok_or_else(|| {
        SolverError::Checkpoint(format!(
            "muscle {index} of a knee checkpoint does not exist"
        ))
    })
}

fn write_sample(out: &mut CheckpointWriter, sample: &StressSample) {
    out.f64(sample.time);
    out.f64(sample.flexion);
    out.f64s(&sample.vm95);
    out.u64(sample.location.len() as u64);
    for location in &sample.location {
        for count in [
            location.origin,
            location.insertion,
            location.interface,
            location.belly,
        ] {
            out.u64(count as u64);
        }
    }
    out.f64(sample.min_jacobian_ratio);
}

fn read_sample(input: &mut CheckpointReader) -> Result<StressSample, SolverError> {
    let time = input.f64()?;
    let flexion = input.f64()?;
    let vm95 = input.f64s()?;
    let locations = input.index()?;
    let location = (0..locations)
        .map(|_| {
            Ok(PeakLocation {
                origin: input.index()?,
                insertion: input.index()?,
                interface: input.index()?,
                belly: input.index()?,
            })
        })
        .collect::<Result<_, SolverError>>()?;
    Ok(StressSample {
        time,
        flexion,
        vm95,
        location,
        min_jacobian_ratio: input.f64()?,
    })
}

fn write_tendon_state(out: &mut CheckpointWriter, state: &TendonState) {
    for value in [
        state.knee_angle,
        state.quadriceps_tension,
        state.tendon_force,
        state.tendon_length,
        state.tendon_strain,
        state.force_ratio,
        state.pose.centre.x,
        state.pose.centre.y,
        state.pose.centre.z,
        state.pose.flexion,
        state.pose.groove_coordinate,
    ] {
        out.f64(value);
    }
    out.u64(state.beyond_table as u64);
}

fn read_tendon_state(input: &mut CheckpointReader) -> Result<TendonState, SolverError> {
    let mut values = [0.0; 11];
    for value in &mut values {
        *value = input.f64()?;
    }
    let [
        knee_angle,
        quadriceps_tension,
        tendon_force,
        tendon_length,
        tendon_strain,
        force_ratio,
        x,
        y,
        z,
        flexion,
        groove_coordinate,
    ] = values;
    Ok(TendonState {
        knee_angle,
        quadriceps_tension,
        tendon_force,
        tendon_length,
        tendon_strain,
        force_ratio,
        pose: PatellaPose {
            centre: nalgebra::Vector3::new(x, y, z),
            flexion,
            groove_coordinate,
        },
        beyond_table: input.u64()? != 0,
    })
}

fn write_plausibility(out: &mut CheckpointWriter, sample: &PlausibilitySample) {
    for value in [
        sample.time,
        sample.flexion,
        sample.tendon_force,
        sample.extensor_moment,
        sample.fiber_stretch_median,
        sample.fiber_stretch_p95,
    ] {
        out.f64(value);
    }
    for values in [
        &sample.insertion_pull,
        &sample.femur_interface_force,
        &sample.femur_interface_along_pull,
        &sample.femur_contact_force,
        &sample.tendon_peak,
    ] {
        out.f64s(values);
    }
}

fn read_plausibility(input: &mut CheckpointReader) -> Result<PlausibilitySample, SolverError> {
    let mut scalars = [0.0; 6];
    for value in &mut scalars {
        *value = input.f64()?;
    }
    let [
        time,
        flexion,
        tendon_force,
        extensor_moment,
        fiber_stretch_median,
        fiber_stretch_p95,
    ] = scalars;
    Ok(PlausibilitySample {
        time,
        flexion,
        tendon_force,
        extensor_moment,
        fiber_stretch_median,
        fiber_stretch_p95,
        insertion_pull: input.f64s()?,
        femur_interface_force: input.f64s()?,
        femur_interface_along_pull: input.f64s()?,
        femur_contact_force: input.f64s()?,
        tendon_peak: input.f64s()?,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every field of a sample, a tendon row and a plausibility sample comes back bit
    /// for bit (the tables of a resumed squat are built from them).
    #[test]
    fn samples_and_rows_round_trip_bit_for_bit() {
        let sample = StressSample {
            time: 0.1 + 0.2,
            flexion: 1.0 / 3.0,
            vm95: vec![1.5e3, f64::MIN_POSITIVE, 7.0],
            location: vec![PeakLocation {
                origin: 1,
                insertion: 2,
                interface: 3,
                belly: 4,
            }],
            min_jacobian_ratio: 0.9,
        };
        let state = TendonState {
            knee_angle: 0.7,
            quadriceps_tension: 812.25,
            tendon_force: 400.0 / 3.0,
            tendon_length: 0.05,
            tendon_strain: 0.012,
            force_ratio: 0.6,
            pose: PatellaPose {
                centre: nalgebra::Vector3::new(0.01, 0.02, -0.003),
                flexion: 0.3,
                groove_coordinate: 0.004,
            },
            beyond_table: true,
        };
        let plausibility = PlausibilitySample {
            time: 0.5,
            flexion: 0.2,
            insertion_pull: vec![1.0, 2.0],
            tendon_force: 3.0,
            extensor_moment: 4.0,
            fiber_stretch_median: 1.1,
            fiber_stretch_p95: 1.2,
            femur_interface_force: vec![5.0],
            femur_interface_along_pull: vec![6.0],
            femur_contact_force: vec![],
            tendon_peak: vec![7.0, 8.0],
        };
        let mut out = CheckpointWriter::new();
        write_sample(&mut out, &sample);
        write_tendon_state(&mut out, &state);
        write_plausibility(&mut out, &plausibility);
        let bytes = out.into_bytes();
        let mut input = CheckpointReader::new(&bytes);
        assert_eq!(read_sample(&mut input).unwrap(), sample);
        assert_eq!(read_tendon_state(&mut input).unwrap(), state);
        assert_eq!(read_plausibility(&mut input).unwrap(), plausibility);
        input.finish().unwrap();
        // A damaged state is refused, not read as zeros.
        let mut short = CheckpointReader::new(&bytes[..bytes.len() - 3]);
        read_sample(&mut short).unwrap();
        read_tendon_state(&mut short).unwrap();
        assert!(read_plausibility(&mut short).is_err());
    }
}
