//! When a run writes a frame: [`FrameSchedule`].
//!
//! The solvers record at their own instants (implicit increments, explicit history rows),
//! which rarely fall on round times. A frame is written at the first recorded instant at
//! or after each multiple of the output interval, at or after each requested instant
//! (e.g. the knee passing 90°), at the start (t = 0, when the solver records it) and at
//! the end, so that the frames a user opens are the ones a study reports.

/// The frame times of one run (see the module documentation).
#[derive(Debug, Clone)]
pub struct FrameSchedule {
    interval: f64,
    next: f64,
    /// Requested instants not framed yet, in increasing order [s].
    instants: Vec<f64>,
    end_time: f64,
}

impl FrameSchedule {
    /// Frames every `interval` [s] (0: none at all) up to `end_time` [s], and at each of
    /// `instants` [s].
    pub fn new(interval: f64, end_time: f64, instants: &[f64]) -> Self {
        let mut instants = instants.to_vec();
        instants.sort_by(f64::total_cmp);
        FrameSchedule {
            interval,
            next: interval,
            instants,
            end_time,
        }
    }

    /// Whether the instant `time` [s], recorded after every earlier one, gets a frame.
    pub fn due(&mut self, time: f64) -> bool {
        if self.interval <= 0.0 {
            return false;
        }
        let tolerance = 1e-9 * self.end_time.max(self.interval);
        let mut due =
            time == 0.0 || time >= self.next - tolerance || time >= self.end_time - tolerance;
        if time >= self.next - tolerance {
            self.next = ((time / self.interval + 1e-9).floor() + 1.0) * self.interval;
        }
        while self
            .instants
            .first()
            .is_some_and(|&t| time >= t - tolerance)
        {
            self.instants.remove(0);
            due = true;
        }
        due
    }
}

/// A [`FrameSchedule`] followed instant by instant, remembering whether the last instant
/// was a frame: where a run takes its checkpoints (after a framed instant, once). A run
/// kept in memory asks for (and drops) a checkpoint at the same instants as `musclefem run`
/// would: a checkpoint makes the implicit solver factorize afresh, so the numbers are then
/// the command's to the last digit.
#[derive(Debug, Clone)]
pub struct FrameInstants {
    schedule: FrameSchedule,
    due: bool,
}

impl FrameInstants {
    pub fn new(schedule: FrameSchedule) -> Self {
        FrameInstants {
            schedule,
            due: false,
        }
    }

    /// A recorded instant `time` [s] (the start included): whether it gets a frame.
    pub fn reached(&mut self, time: f64) -> bool {
        self.due = self.schedule.due(time);
        self.due
    }

    /// Whether the last instant reached was a frame, answered once (for
    /// `Observer::wants_checkpoint`).
    pub fn take_due(&mut self) -> bool {
        std::mem::take(&mut self.due)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frames(schedule: &mut FrameSchedule, times: &[f64]) -> Vec<f64> {
        times.iter().copied().filter(|&t| schedule.due(t)).collect()
    }

    #[test]
    fn frames_fall_on_the_interval_the_instants_and_the_end() {
        // Increments of 0.02 s from 0.02 (no t = 0 record), 0.1 s frames, the knee's 90°
        // at 1.04 s and 45° at 0.517 s, the run ending at 2.08 s.
        let times: Vec<f64> = (1..=104).map(|k| 0.02 * k as f64).collect();
        let mut schedule = FrameSchedule::new(0.1, 2.08, &[1.04, 0.517]);
        let framed = frames(&mut schedule, &times);
        let expect = |t: f64| framed.iter().any(|f| (f - t).abs() < 1e-9);
        for t in [0.1, 0.2, 0.5, 0.52, 1.0, 1.04, 1.1, 2.0, 2.08] {
            assert!(expect(t), "no frame at {t}: {framed:?}");
        }
        // 20 multiples of 0.1, the two instants and the end.
        assert_eq!(framed.len(), 20 + 2 + 1, "{framed:?}");
    }

    #[test]
    fn the_explicit_first_record_at_zero_is_framed_and_zero_interval_writes_none() {
        let mut schedule = FrameSchedule::new(0.25, 1.0, &[]);
        assert_eq!(
            frames(&mut schedule, &[0.0, 0.1, 0.25, 0.3, 0.6, 1.0]),
            [0.0, 0.25, 0.6, 1.0]
        );
        let mut none = FrameSchedule::new(0.0, 1.0, &[0.5]);
        assert!(frames(&mut none, &[0.0, 0.5, 1.0]).is_empty());
    }
}
