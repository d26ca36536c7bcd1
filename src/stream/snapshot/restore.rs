//! A snapshot taken from and restored into a [`Pipeline`]: capture of its models and warm
//! state, and the checked restore.

use std::sync::Arc;

use super::{AxisSnapshot, Compat, Snapshot, SnapshotError, StoredModel};
use crate::model::Predict;
use crate::stream::model_slot::InstalledModel;
use crate::stream::pipeline::Pipeline;
use crate::stream::warm::{AxisWarm, StreamWarm};

impl Snapshot {
    /// A snapshot of the installed models (an axis may have none) and the warm states; fails
    /// when an installed model's kind cannot be stored.
    pub fn capture(
        compat: Compat,
        models: [Option<Arc<InstalledModel>>; 3],
        warm: [AxisWarm; 3],
        stream: StreamWarm,
    ) -> Result<Self, SnapshotError> {
        let mut axes = Vec::with_capacity(3);
        for (axis, (m, w)) in models.into_iter().zip(warm).enumerate() {
            let model = match m {
                None => None,
                Some(m) => Some(StoredModel {
                    model: m.model.state().ok_or(SnapshotError::NotStorable(axis))?,
                    scaler: m.scaler,
                    version: m.version,
                }),
            };
            axes.push(AxisSnapshot { model, warm: w });
        }
        let axes = <[AxisSnapshot; 3]>::try_from(axes).map_err(|_| SnapshotError::NotStorable(3))?;
        Ok(Self { compat, axes, stream })
    }

    /// A snapshot of everything `pipeline` holds (see [`Snapshot::capture`]).
    pub fn of_pipeline(pipeline: &Pipeline) -> Result<Self, SnapshotError> {
        let models = [0, 1, 2].map(|axis| pipeline.model_slot(axis).and_then(|slot| (*slot.load()).clone()));
        Self::capture(Compat::of(pipeline.config()), models, pipeline.warm_state(), pipeline.stream_state())
    }

    /// Installs the models and restores the warm and shared state into `pipeline` (one that
    /// has processed no sample), after checking the snapshot against the pipeline's
    /// configuration and trying it on a scratch pipeline of the same configuration; on an
    /// error the pipeline is unchanged.
    pub fn restore_into(&self, pipeline: &mut Pipeline) -> Result<(), SnapshotError> {
        self.compat.check(&Compat::of(pipeline.config()))?;
        self.validate()?;
        let mut scratch =
            Pipeline::new(pipeline.config().clone()).map_err(|e| SnapshotError::Incompatible(e.to_string()))?;
        self.apply(&mut scratch)?;
        self.apply(pipeline)
    }

    fn apply(&self, pipeline: &mut Pipeline) -> Result<(), SnapshotError> {
        let warm = self.axes.each_ref().map(|a| a.warm.clone());
        pipeline.restore_state(&warm, &self.stream).map_err(|e| SnapshotError::Incompatible(e.to_string()))?;
        for (axis, a) in self.axes.iter().enumerate() {
            let Some(m) = &a.model else { continue };
            let model: Arc<dyn Predict + Send + Sync> = Arc::new(m.model.clone());
            pipeline
                .install_model(axis, model, m.scaler, m.version)
                .map_err(|e| SnapshotError::Incompatible(format!("axis {axis}: {e}")))?;
        }
        Ok(())
    }
}
