//! The interface between the filter and an optional state block ([`crate::state::OptionalBlock`]):
//! what the filter's one propagation path and one update path, its protections (variance floor
//! and ceiling, freezing), its resets and restarts ask of every block, and what blocks hand
//! each other through it. A block implements [`OptionalModel`] for its configuration and
//! [`OptionalStates`] for its states in its own module; `crate::filter`'s registration
//! (`optional_blocks!` in `filter/blocks.rs`) composes the blocks in order, statically: no
//! `dyn`, no allocation, every step a fixed sequence of calls.
//!
//! Two kinds of block exist, and the coupling between them goes through this interface only:
//! * a **measured** border, which a measurement sees directly (`z = H_x x + h_ε ε + v`, `h_ε`
//!   the measurement's [`crate::measurement::LinearMeasurement::border_coefficient`]); it is a
//!   first-order Gauss–Markov block (`ε ← φ ε`) of three states, one per measured axis. At
//!   most one is in use.
//! * a **bias** border, which acts on the navigation as equivalent sensor biases (its
//!   transition `Γ = E M`, see [`crate::structured`]); it carries its cross-covariance `B`
//!   with the measured border, and so takes the measured border's decay `φ` in propagation,
//!   its products and freezing in an update and its ceiling scales in the protections, and
//!   gives the measured border's cross-covariance its bias inputs `M Bᵀ`.
//!
//! The registration calls the blocks in its order, the measured border before any bias border
//! (a bias border reads the measured border's ceiling scales after they are applied).

use nalgebra::Vector3;

use crate::block::{Block, Row};
use crate::filter::ErrorState;
use crate::measurement::MeasurementJacobian;
use crate::state::{BlockMask, OptionalBlock, STATE_DIMENSION};
use crate::structured::{BorderBiasInputs, Cholesky3, StateRows, StructuredModel};
use crate::NavError;

/// What an update adds to the 24-state quantities for the measured border, and the border's
/// own products.
#[derive(Debug, Clone, Copy)]
pub(crate) struct MeasuredBorder {
    /// `h_ε`.
    pub(crate) coefficient: f64,
    /// `h_ε (G + Gᵀ) + h_ε² P_εε`, added to `S`.
    pub(crate) projected: Block,
    /// Rows of `M_ε = Gᵀ + h_ε P_εε`.
    pub(crate) products: [Row; 3],
    /// Whether the border is frozen (its gain rows zero in every update).
    pub(crate) frozen: bool,
}

/// What an update hands to the blocks' preparation: the measurement's Jacobian and observed
/// blocks, the core gains `K_x`, `M_x` and the frozen blocks, `S`'s factor and the innovation.
pub(crate) struct UpdateInputs<'a> {
    pub(crate) jacobian: (&'a MeasurementJacobian, &'a [bool; STATE_DIMENSION / 3]),
    pub(crate) gains: &'a StateRows,
    pub(crate) products: &'a StateRows,
    pub(crate) frozen: &'a BlockMask,
    pub(crate) cholesky: &'a Cholesky3,
    pub(crate) innovation: Row,
}

impl UpdateInputs<'_> {
    /// The core's part: `K_x`, `M_x` and the frozen blocks.
    #[inline]
    pub(crate) fn core(&self) -> (&StateRows, &StateRows, &BlockMask) {
        (self.gains, self.products, self.frozen)
    }

    /// `S⁻¹ r` for a row `r`.
    #[inline]
    pub(crate) fn solve(&self, row: Row) -> Row {
        self.cholesky.solve(row)
    }
}

/// A block's configuration: its model, off by [`OptionalModel::OFF`] (the paper's 24 states).
pub(crate) trait OptionalModel: Copy {
    /// The model that leaves the block out.
    const OFF: Self;

    /// Whether the model asks for the block.
    fn in_use(&self) -> bool;

    /// The model's own check (its values, and that its block is compiled in when in use).
    ///
    /// # Errors
    /// [`NavError::InvalidConfiguration`] for a model the block refuses.
    fn check(&self) -> Result<(), NavError>;

    /// Each of the block's states' prior variance, in layout order, into `variances` (the
    /// block's states only).
    fn write_prior_variances(&self, variances: &mut [f64]);
}

/// A block's states as the filter holds them: every step of the filter that touches an
/// optional block goes through these methods. Defaults are those of a block that does not
/// take part in a step; a block not in use ([`OptionalStates::in_use`] false) is only asked
/// [`OptionalStates::scale_cross_row`] (a no-op on its zero rows).
pub(crate) trait OptionalStates {
    /// The block's configuration.
    type Model: OptionalModel;
    /// The block's first layout block.
    const FIRST_BLOCK: OptionalBlock;
    /// Number of the block's states (its layout blocks' dimensions summed).
    const DIMENSION: usize;
    /// Everything zero, the model off: written into the filter's slot before
    /// [`OptionalStates::start`], so a large block is never built on the stack and moved.
    const EMPTY: Self;

    /// On [`OptionalStates::EMPTY`] states, in place: `model` and its prior. The caller has
    /// checked `model`.
    fn start(&mut self, model: Self::Model);

    /// Whether the block is in use.
    fn in_use(&self) -> bool;

    /// Whether `block` (one of this block's layout blocks) is frozen.
    fn block_frozen(&self, _block: OptionalBlock) -> bool {
        false
    }

    /// Freezes `block` (one of this block's layout blocks) or releases it.
    fn freeze(&mut self, _block: OptionalBlock, _frozen: bool) {}

    /// Whether this is a measured border in use.
    fn is_measured(&self) -> bool {
        false
    }

    /// Whether this is a bias border in use (it couples to the measured border).
    fn couples_to_measured(&self) -> bool {
        false
    }

    /// A bias border's `M Bᵀ`: the bias inputs the measured border's cross-covariance
    /// propagation folds in.
    fn measured_cross_inputs(&self, _model: &StructuredModel) -> Option<[Block; 2]> {
        None
    }

    /// Propagation, first step: the new values into spare buffers, nothing the filter reads
    /// changed; `false` if one is not finite. `measured_inputs`: a bias border's
    /// [`OptionalStates::measured_cross_inputs`], for the measured border.
    fn prepare_propagation(
        &mut self,
        _model: &StructuredModel,
        _open_loop: bool,
        _measured_inputs: Option<&[Block; 2]>,
    ) -> bool {
        true
    }

    /// The bias inputs the core propagation kernel folds in (a bias border's).
    fn kernel_inputs(&self) -> Option<&BorderBiasInputs> {
        None
    }

    /// Open loop: the block's part of the propagated core state.
    fn add_state_increment(&self, _state: &mut ErrorState) {}

    /// The measured border's decay `φ` over `interval_s`.
    fn measured_decay(&self, _interval_s: f64) -> Option<f64> {
        None
    }

    /// Propagation, last step: the prepared values made current; `measured_decay` the
    /// measured border's `φ`, given to a bias border.
    fn commit_propagation(&mut self, _measured_decay: Option<f64>) {}

    /// The measured border's part of an update with Jacobian `H_x` (`observed` its non-zero
    /// 3×3 blocks) and coefficient `h_ε`.
    fn measured_border(
        &self,
        _jacobian: &MeasurementJacobian,
        _observed: &[bool; STATE_DIMENSION / 3],
        _coefficient: f64,
    ) -> Option<MeasuredBorder> {
        None
    }

    /// The measured border's cross-covariance rows `C_j` (added to `M_x`).
    fn measured_rows(&self) -> Option<&StateRows> {
        None
    }

    /// The measured border's `h_ε ε̂`, subtracted from the innovation.
    fn predicted_residual(&self, _coefficient: f64) -> Option<Vector3<f64>> {
        None
    }

    /// Update, first step: the new values into spare buffers; `false` if one is not finite
    /// (nothing the filter reads changed). `measured`: the measured border's part. Asked of
    /// every block: one not in use (a measured border without `measured`) returns `true`.
    fn prepare_update(
        &mut self,
        _measured: Option<&MeasuredBorder>,
        _inputs: &UpdateInputs<'_>,
    ) -> bool {
        true
    }

    /// Update, last step: the prepared values made current.
    fn commit_update(&mut self) {}

    /// `C ← J C`, `J` the identity but `J_ϑϑ = attitude` and `J_ψψ = installation`; with
    /// `reset_estimate` (the closed-loop reset) a fed-back estimate is also zeroed.
    fn transform_cross_rows(&mut self, _attitude: &Block, _installation: &Block, _reset: bool) {}

    /// Row `index` of the cross-covariance times `scale` (that core state's uncertainty was
    /// scaled).
    fn scale_cross_row(&mut self, _index: usize, _scale: f64) {}

    /// The variance floor and ceiling on the block's states (`floor`, `ceiling`: the block's
    /// own, layout order); `measured_scales`: the measured border's ceiling scales, for a
    /// bias border's `B`. Returns whether anything changed and, for the measured border, its
    /// scales when a ceiling was crossed.
    fn protect_variances(
        &mut self,
        _floor: &[f64],
        _ceiling: &[f64],
        _measured_scales: Option<&Row>,
    ) -> (bool, Option<Row>) {
        (false, None)
    }

    /// Whether the dense reference covers the block as it is (in use or not).
    #[cfg(any(test, feature = "dense-reference"))]
    fn has_dense_reference(&self) -> bool {
        !self.in_use()
    }

    /// The measured border's dense propagation with `transition(c) = F c`; `false` (nothing
    /// changed) if not finite.
    #[cfg(any(test, feature = "dense-reference"))]
    fn propagate_dense<F>(&mut self, _interval_s: f64, _transition: &F) -> bool
    where
        F: Fn(&nalgebra::SVector<f64, STATE_DIMENSION>) -> nalgebra::SVector<f64, STATE_DIMENSION>,
    {
        true
    }

    /// The measured border as the dense reference reads it: `C`, `P_εε`, `ε̂`, frozen.
    #[cfg(any(test, feature = "dense-reference"))]
    fn measured_dense(&self) -> Option<DenseBorder> {
        None
    }

    /// Replaces the measured border's `ε̂`, `P_εε` and `C` (the dense reference's result).
    #[cfg(any(test, feature = "dense-reference"))]
    fn set_measured_dense(&mut self, _border: &DenseBorder) {}
}

/// The measured border as the dense reference reads and writes it.
#[cfg(any(test, feature = "dense-reference"))]
#[derive(Debug, Clone, Copy)]
pub(crate) struct DenseBorder {
    /// `C = P_xε` (24×3).
    pub(crate) cross: nalgebra::SMatrix<f64, STATE_DIMENSION, 3>,
    /// `P_εε`.
    pub(crate) covariance: nalgebra::Matrix3<f64>,
    /// `ε̂`.
    pub(crate) estimate: Vector3<f64>,
    /// Whether the border is frozen.
    pub(crate) frozen: bool,
}

/// The layout states of `T` (indices in the layout with every block).
pub(crate) const fn layout_states<T: OptionalStates>() -> core::ops::Range<usize> {
    T::FIRST_BLOCK.index()..T::FIRST_BLOCK.index() + T::DIMENSION
}

/// Whether `block` is one of `T`'s layout blocks.
pub(crate) const fn owns<T: OptionalStates>(block: OptionalBlock) -> bool {
    let states = layout_states::<T>();
    block.index() >= states.start && block.index() < states.end
}
