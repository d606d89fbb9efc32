//! Checkpoints: the state a run needs to go on from a recorded instant as if it had never
//! stopped.
//!
//! A solver hands its observer a [`Checkpoint`] right after a recorded row when the
//! observer asks for one ([`super::Observer::wants_checkpoint`]); [`super::resume`] starts
//! the same problem from it. The state is everything that evolves: nodal kinematics and
//! force histories, the energy books, every material point's accepted and trial state,
//! the solver's step control, and each interaction's bonds. What is fixed by the problem
//! (reference geometry, masses, element data) is rebuilt, not stored, so a checkpoint
//! resumes only the problem it was taken from; the reader checks every array's length
//! against the rebuilt problem.
//!
//! The bytes are little-endian: every number as its 64-bit pattern, every array with its
//! length first. Floating-point values round-trip bit for bit, so a resumed run computes
//! the same numbers as an uninterrupted one.

use nalgebra::SMatrix;

use super::SolverError;

/// The state of a run at a recorded instant (see the module documentation).
#[derive(Debug, Clone, PartialEq)]
pub struct Checkpoint {
    /// `explicit` or `implicit`: the solver that wrote it.
    pub solver: String,
    /// The recorded instant it continues after [s].
    pub time: f64,
    /// The solver's state, written by a [`CheckpointWriter`].
    pub state: Vec<u8>,
}

/// Writes a solver's state.
#[derive(Debug, Default)]
pub struct CheckpointWriter {
    bytes: Vec<u8>,
}

impl CheckpointWriter {
    pub fn new() -> Self {
        Self::default()
    }

    /// The bytes written.
    pub fn into_bytes(self) -> Vec<u8> {
        self.bytes
    }

    pub fn u64(&mut self, value: u64) {
        self.bytes.extend_from_slice(&value.to_le_bytes());
    }

    pub fn f64(&mut self, value: f64) {
        self.u64(value.to_bits());
    }

    /// `None` as a 0 flag, `Some(x)` as 1 and x.
    pub fn optional_f64(&mut self, value: Option<f64>) {
        self.u64(value.is_some() as u64);
        self.f64(value.unwrap_or(0.0));
    }

    pub fn f64s(&mut self, values: &[f64]) {
        self.u64(values.len() as u64);
        values.iter().for_each(|&x| self.f64(x));
    }

    pub fn u32s(&mut self, values: &[u32]) {
        self.u64(values.len() as u64);
        values.iter().for_each(|&x| self.u64(x as u64));
    }

    /// Vectors, matrices, Voigt stresses: any fixed-size matrix of f64.
    pub fn matrices<const R: usize, const C: usize>(&mut self, values: &[SMatrix<f64, R, C>]) {
        self.u64(values.len() as u64);
        for value in values {
            value.iter().for_each(|&x| self.f64(x));
        }
    }

    pub fn text(&mut self, text: &str) {
        self.bytes(text.as_bytes());
    }

    /// Raw bytes (another writer's output), with their length first.
    pub fn bytes(&mut self, bytes: &[u8]) {
        self.u64(bytes.len() as u64);
        self.bytes.extend_from_slice(bytes);
    }
}

/// Reads what a [`CheckpointWriter`] wrote, in the same order, into the arrays of a
/// rebuilt problem (which must have the lengths the checkpoint has).
#[derive(Debug)]
pub struct CheckpointReader<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl<'a> CheckpointReader<'a> {
    pub fn new(bytes: &'a [u8]) -> Self {
        Self { bytes, at: 0 }
    }

    fn error(&self, what: String) -> SolverError {
        SolverError::Checkpoint(format!("at byte {}: {what}", self.at))
    }

    pub fn u64(&mut self) -> Result<u64, SolverError> {
        let end = self.at + 8;
        let bytes = self
            .bytes
            .get(self.at..end)
            .ok_or_else(|| self.error("the checkpoint ends early".into()))?;
        self.at = end;
        Ok(u64::from_le_bytes(bytes.try_into().expect("8 bytes")))
    }

    pub fn f64(&mut self) -> Result<f64, SolverError> {
        Ok(f64::from_bits(self.u64()?))
    }

    pub fn optional_f64(&mut self) -> Result<Option<f64>, SolverError> {
        let present = self.u64()? != 0;
        let value = self.f64()?;
        Ok(present.then_some(value))
    }

    /// A usize stored as u64 (a count or an index).
    pub fn index(&mut self) -> Result<usize, SolverError> {
        let value = self.u64()?;
        usize::try_from(value).map_err(|_| self.error(format!("index {value} too large")))
    }

    /// The length of the next array, which must be `expected` (the rebuilt problem's).
    fn length(&mut self, what: &str, expected: usize) -> Result<(), SolverError> {
        let found = self.u64()?;
        if found != expected as u64 {
            return Err(self.error(format!(
                "{what}: {found} values in the checkpoint, {expected} in the problem (the \
                 checkpoint belongs to another model)"
            )));
        }
        Ok(())
    }

    pub fn f64s_into(&mut self, what: &str, values: &mut [f64]) -> Result<(), SolverError> {
        self.length(what, values.len())?;
        for x in values {
            *x = self.f64()?;
        }
        Ok(())
    }

    /// An array of any length (state the problem does not size, e.g. a history).
    pub fn f64s(&mut self) -> Result<Vec<f64>, SolverError> {
        let count = self.index()?;
        if count > (self.bytes.len() - self.at) / 8 {
            return Err(self.error(format!("{count} values announced, fewer stored")));
        }
        (0..count).map(|_| self.f64()).collect()
    }

    /// A list of u32 of any length (state the problem does not size).
    pub fn u32s(&mut self) -> Result<Vec<u32>, SolverError> {
        let count = self.index()?;
        if count > (self.bytes.len() - self.at) / 8 {
            return Err(self.error(format!("{count} values announced, fewer stored")));
        }
        (0..count)
            .map(|_| {
                let value = self.u64()?;
                u32::try_from(value).map_err(|_| self.error(format!("{value} is not a u32")))
            })
            .collect()
    }

    pub fn u32s_into(&mut self, what: &str, values: &mut [u32]) -> Result<(), SolverError> {
        self.length(what, values.len())?;
        for x in values {
            let value = self.u64()?;
            *x = u32::try_from(value).map_err(|_| self.error(format!("{what}: {value}")))?;
        }
        Ok(())
    }

    pub fn matrices_into<const R: usize, const C: usize>(
        &mut self,
        what: &str,
        values: &mut [SMatrix<f64, R, C>],
    ) -> Result<(), SolverError> {
        self.length(what, values.len())?;
        for value in values {
            for x in value.iter_mut() {
                *x = self.f64()?;
            }
        }
        Ok(())
    }

    pub fn text(&mut self) -> Result<String, SolverError> {
        let bytes = self.bytes()?;
        String::from_utf8(bytes).map_err(|_| self.error("a text that is not UTF-8".into()))
    }

    /// What [`CheckpointWriter::bytes`] wrote.
    pub fn bytes(&mut self) -> Result<Vec<u8>, SolverError> {
        let length = self.index()?;
        let bytes = self
            .bytes
            .get(self.at..self.at.saturating_add(length))
            .ok_or_else(|| self.error("the checkpoint ends early".into()))?
            .to_vec();
        self.at += length;
        Ok(bytes)
    }

    /// Fails unless every byte was read (a checkpoint of a larger problem).
    pub fn finish(&self) -> Result<(), SolverError> {
        if self.at != self.bytes.len() {
            return Err(self.error(format!(
                "{} bytes left over (the checkpoint belongs to another model)",
                self.bytes.len() - self.at
            )));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Matrix3, Vector3};

    #[test]
    fn values_round_trip_bit_for_bit_and_lengths_are_checked() {
        let mut writer = CheckpointWriter::new();
        writer.f64(-0.0);
        writer.optional_f64(None);
        writer.optional_f64(Some(f64::NAN));
        writer.f64s(&[1.0 / 3.0, f64::MIN_POSITIVE]);
        writer.matrices(&[Matrix3::new(1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.1)]);
        writer.u32s(&[7, u32::MAX]);
        writer.text("vastus_lateralis");
        let bytes = writer.into_bytes();

        let mut reader = CheckpointReader::new(&bytes);
        assert_eq!(reader.f64().unwrap().to_bits(), (-0.0f64).to_bits());
        assert_eq!(reader.optional_f64().unwrap(), None);
        assert!(reader.optional_f64().unwrap().unwrap().is_nan());
        let mut values = [0.0; 2];
        reader.f64s_into("values", &mut values).unwrap();
        assert_eq!(values, [1.0 / 3.0, f64::MIN_POSITIVE]);
        let mut matrices = [Matrix3::zeros()];
        reader.matrices_into("F", &mut matrices).unwrap();
        assert_eq!(matrices[0][(2, 2)], 9.1);
        let mut ids = [0; 2];
        reader.u32s_into("ids", &mut ids).unwrap();
        assert_eq!(ids, [7, u32::MAX]);
        assert_eq!(reader.text().unwrap(), "vastus_lateralis");
        reader.finish().unwrap();

        // A problem of another size is refused, naming the array.
        let mut reader = CheckpointReader::new(&bytes);
        reader.f64().unwrap();
        reader.optional_f64().unwrap();
        reader.optional_f64().unwrap();
        let mut three = [Vector3::zeros(); 3];
        let error = reader.matrices_into("velocity", &mut three).unwrap_err();
        assert!(error.to_string().contains("velocity: 2 values"), "{error}");
        // Truncated bytes are an error, not a panic.
        let mut reader = CheckpointReader::new(&bytes[..12]);
        reader.f64().unwrap();
        assert!(reader.u64().is_err());
    }
}
