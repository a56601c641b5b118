//! The border as a bias border of [`crate::block_interface`]: the filter's propagation,
//! update, reset and protections reach it through [`OptionalStates`] only.

use super::ImuErrorStates;
use crate::block::{Block, Row};
use crate::block_interface::{MeasuredBorder, OptionalStates, UpdateInputs};
use crate::filter::ErrorState;
use crate::imu_error::IMU_ERROR_DIMENSION;
use crate::state::OptionalBlock;
use crate::structured::{BorderBiasInputs, StructuredModel};

impl OptionalStates for ImuErrorStates {
    type Model = super::ImuErrorModel;
    const FIRST_BLOCK: OptionalBlock = OptionalBlock::GyroNonOrthogonality;
    const DIMENSION: usize = IMU_ERROR_DIMENSION;
    const EMPTY: Self = Self::EMPTY;

    fn start(&mut self, model: super::ImuErrorModel) {
        ImuErrorStates::start(self, model);
    }

    fn in_use(&self) -> bool {
        self.is_enabled()
    }

    fn block_frozen(&self, block: OptionalBlock) -> bool {
        ImuErrorStates::is_frozen(self, block)
    }

    fn freeze(&mut self, block: OptionalBlock, frozen: bool) {
        self.set_frozen(block, frozen);
    }

    fn couples_to_measured(&self) -> bool {
        self.is_enabled()
    }

    fn measured_cross_inputs(&self, model: &StructuredModel) -> Option<[Block; 2]> {
        self.is_enabled().then(|| self.gnss_bias_inputs(model))
    }

    fn prepare_propagation(
        &mut self,
        model: &StructuredModel,
        open_loop: bool,
        _measured_inputs: Option<&[Block; 2]>,
    ) -> bool {
        ImuErrorStates::prepare_propagation(self, model, open_loop)
    }

    fn kernel_inputs(&self) -> Option<&BorderBiasInputs> {
        self.is_enabled().then(|| self.propagation_inputs())
    }

    fn add_state_increment(&self, state: &mut ErrorState) {
        if self.is_enabled() {
            for (value, delta) in state.iter_mut().zip(self.state_increment()) {
                *value += delta;
            }
        }
    }

    fn commit_propagation(&mut self, measured_decay: Option<f64>) {
        // `B = cov(ε_measured, ε)` decays with the measured border.
        ImuErrorStates::commit_propagation(self, measured_decay);
    }

    #[inline(always)]
    fn prepare_update(
        &mut self,
        measured: Option<&MeasuredBorder>,
        inputs: &UpdateInputs<'_>,
    ) -> bool {
        if !self.is_enabled() {
            return true;
        }
        let solve = |row| inputs.solve(row);
        ImuErrorStates::prepare_update(
            self,
            inputs.jacobian,
            inputs.core(),
            solve,
            inputs.innovation,
            measured.map(|border| (border.coefficient, &border.products, border.frozen)),
        )
    }

    fn commit_update(&mut self) {
        ImuErrorStates::commit_update(self);
    }

    fn transform_cross_rows(&mut self, attitude: &Block, installation: &Block, reset: bool) {
        if reset {
            self.reset(attitude, installation);
        } else {
            ImuErrorStates::transform_cross_rows(self, attitude, installation);
        }
    }

    fn scale_cross_row(&mut self, index: usize, scale: f64) {
        ImuErrorStates::scale_cross_row(self, index, scale);
    }

    fn protect_variances(
        &mut self,
        floor: &[f64],
        ceiling: &[f64],
        measured_scales: Option<&Row>,
    ) -> (bool, Option<Row>) {
        // `B = cov(ε_measured, ε)` takes the measured border's scaling on its rows.
        if let Some(scales) = measured_scales {
            self.scale_gnss_rows(scales);
        }
        let bounds = (
            floor.first_chunk::<IMU_ERROR_DIMENSION>(),
            ceiling.first_chunk::<IMU_ERROR_DIMENSION>(),
        );
        match bounds {
            (Some(floor), Some(ceiling)) => (
                ImuErrorStates::protect_variances(self, floor, ceiling),
                None,
            ),
            _ => (false, None),
        }
    }
}
