//! Field-by-field conversion between the iceoryx2 wire types and the pipeline's records.

use crate::ipc::{CompSample, RawSample, StatusEvent, StatusSample};
use crate::stream::{InputSample, OutputSample, PipelineStats};

/// The pipeline input of a raw wire sample (flags and temperature carried over).
pub fn input_from_raw(raw: &RawSample) -> InputSample {
    InputSample { seq: raw.seq, t_ns: raw.t_ns, rate_dps: raw.rate_dps, temp_c: raw.temp_c, flags: raw.flags }
}

/// The raw wire sample of a pipeline input (what `replay` publishes for a recording's sample);
/// the inverse of [`input_from_raw`].
pub fn raw_from_input(input: &InputSample) -> RawSample {
    RawSample {
        seq: input.seq,
        t_ns: input.t_ns,
        rate_dps: input.rate_dps,
        temp_c: input.temp_c,
        flags: input.flags,
        _pad: 0,
    }
}

/// The pipeline output carried by a compensated wire sample (what `replay` writes); the inverse
/// of [`comp_from_output`].
pub fn output_from_comp(comp: &CompSample) -> OutputSample {
    OutputSample {
        seq: comp.seq,
        t_ns: comp.t_ns,
        rate_dps: comp.rate_dps,
        drift_dps: comp.drift_dps,
        model_version: comp.model_version,
        status: comp.status,
        drift_std_dps: comp.drift_std_dps,
    }
}

/// The wire sample of a pipeline output (the status bits are the same on both sides).
pub fn comp_from_output(out: &OutputSample) -> CompSample {
    CompSample {
        seq: out.seq,
        t_ns: out.t_ns,
        rate_dps: out.rate_dps,
        drift_dps: out.drift_dps,
        model_version: out.model_version,
        status: out.status,
        _pad: 0,
        drift_std_dps: out.drift_std_dps,
    }
}

/// What the daemon itself counts beside the pipeline.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct LoopCounters {
    /// Raw samples received.
    pub samples_in: u64,
    /// Compensated samples published without error.
    pub samples_out: u64,
    /// Compensated samples whose send failed for at least one subscriber.
    pub send_failures: u64,
    /// `seq` of the last raw sample received.
    pub last_seq: u64,
    /// Wall time from the last retrain request to its model's installation (or failure), ns;
    /// live mode: the fit plus at most one sample period; deterministic mode: also the apply
    /// delay. 0 = none yet.
    pub last_retrain_ns: u64,
}

/// A status report from the pipeline's and the loop's counters.
pub fn status_sample(
    event: StatusEvent,
    t_ns: u64,
    stats: &PipelineStats,
    model_version: u64,
    counters: &LoopCounters,
) -> StatusSample {
    StatusSample {
        t_ns,
        samples_in: counters.samples_in,
        samples_out: counters.samples_out,
        rejected: stats.rejected,
        moving: stats.moving,
        gaps: stats.gaps,
        retrains_done: stats.models_installed,
        retrains_skipped: stats.retrain_skipped + stats.retrain_starved,
        retrains_failed: stats.retrain_failed,
        model_version,
        last_seq: counters.last_seq,
        last_retrain_ns: counters.last_retrain_ns,
        event: event as u32,
        _pad: 0,
        send_failures: counters.send_failures,
        invalid: stats.input.invalid,
        spikes: stats.input.spikes,
        duplicates: stats.input.duplicates,
        time_backwards: stats.input.time_backwards,
        seq_skipped: stats.input.seq_skipped,
        restarts: stats.input.restarts,
        detector_onsets: stats.detector.onsets,
        detector_alarms: stats.detector.alarms,
        committed: stats.committed,
        discarded: stats.discarded,
        stuck: stats.input.stuck,
        saturated: stats.input.saturated,
        bad_temperature: stats.input.bad_temperature,
        relearns: stats.detector.relearns,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ipc::RAW_FLAG_MOVING;

    #[test]
    fn fields_are_carried_over() {
        let raw = RawSample { temp_c: 21.5, flags: RAW_FLAG_MOVING, ..RawSample::new(7, 70, [1.0, 2.0, 3.0]) };
        let input = input_from_raw(&raw);
        assert_eq!(
            (input.seq, input.t_ns, input.rate_dps, input.temp_c, input.flags),
            (7, 70, [1.0, 2.0, 3.0], 21.5, 1)
        );
        let out = OutputSample {
            seq: 7,
            t_ns: 70,
            rate_dps: [0.5; 3],
            drift_dps: [0.1; 3],
            model_version: 4,
            status: 0b1010,
            drift_std_dps: [0.01, 0.02, f64::INFINITY],
        };
        let comp = comp_from_output(&out);
        assert_eq!((comp.seq, comp.t_ns, comp.model_version, comp.status, comp._pad), (7, 70, 4, 0b1010, 0));
        assert_eq!((comp.rate_dps, comp.drift_dps), ([0.5; 3], [0.1; 3]));
        assert_eq!(comp.drift_std_dps, [0.01, 0.02, f64::INFINITY]);
        assert_eq!(output_from_comp(&comp), out);
        let back = raw_from_input(&input);
        assert_eq!((back.seq, back.t_ns, back.rate_dps, back.flags, back._pad), (7, 70, [1.0, 2.0, 3.0], 1, 0));
        assert_eq!(back.temp_c.to_bits(), raw.temp_c.to_bits());
        let input = crate::stream::InputCounters { spikes: 6, seq_skipped: 2, ..Default::default() };
        let stats =
            PipelineStats { retrain_skipped: 2, retrain_starved: 3, models_installed: 1, input, ..Default::default() };
        let counters =
            LoopCounters { samples_in: 9, samples_out: 8, send_failures: 1, last_seq: 7, last_retrain_ns: 3 };
        let s = status_sample(StatusEvent::ModelSwapped, 5, &stats, 4, &counters);
        assert_eq!((s.retrains_skipped, s.retrains_done, s.model_version, s.samples_out), (5, 1, 4, 8));
        assert_eq!((s.last_seq, s.last_retrain_ns, s.send_failures), (7, 3, 1));
        assert_eq!((s.spikes, s.seq_skipped, s.duplicates), (6, 2, 0));
        assert_eq!(StatusEvent::from_u32(s.event), Some(StatusEvent::ModelSwapped));
    }
}
