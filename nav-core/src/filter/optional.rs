//! The core's protections for the optional state blocks ([`crate::state::OptionalBlock`]):
//! the variance floor and ceiling ([`ErrorStateFilter::protect_optional_variances`], the
//! rule of [`ErrorStateFilter::protect_variances`]) and freezing
//! ([`ErrorStateFilter::set_optional_block_frozen`]: the block's gain rows zero in every
//! update, as a frozen core block's in
//! [`ErrorStateFilter::update_with_frozen_blocks`]). The frozen flags live in the blocks'
//! own states, read only where a block's gain rows are formed, so the core's
//! [`crate::state::BlockMask`] and the flight without optional blocks are unchanged.

use super::{ErrorStateFilter, FilterConfig};
use crate::state::{OptionalBlock, OPTIONAL_DIMENSION, STATE_DIMENSION};
use crate::NavError;

/// The variance floor and ceiling of every optional state, in layout order after the core's
/// 24 (state `k` here is state `24 + k` of the layout with every block), units of the
/// block, squared.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct OptionalVarianceBounds {
    /// A variance below its floor is raised to it.
    pub floor: [f64; OPTIONAL_DIMENSION],
    /// A variance above its ceiling is scaled back to it with its row and column.
    pub ceiling: [f64; OPTIONAL_DIMENSION],
}

impl OptionalVarianceBounds {
    /// The states of `block` in [`Self::floor`] and [`Self::ceiling`].
    pub fn states(block: OptionalBlock) -> core::ops::Range<usize> {
        let first = block.index().saturating_sub(STATE_DIMENSION);
        first..first.saturating_add(block.dimension())
    }

    /// The bounds as the core's are configured: the floor the square of the block's 1σ
    /// floor (`floor_sigma`, one per block in [`OptionalBlock::ALL`] order), the ceiling the
    /// state's prior variance in `config` times `ceiling_factor²` (a factor of at least 1
    /// puts it at or above the prior). A block not in use has zero bounds (never read).
    ///
    /// # Errors
    /// [`NavError::InvalidConfiguration`] for an invalid `config`, the floor 1σ of a block in
    /// use negative or not finite, or a ceiling factor below 1 or not finite.
    ///
    /// # Examples
    /// ```
    /// use nav_core::filter::{FilterConfig, FilterMode, InitialUncertainty, OptionalVarianceBounds};
    /// use nav_core::state::OptionalBlock;
    /// let initial = InitialUncertainty {
    ///     attitude_rad: 1e-3, position_m: 10.0, velocity_mps: 0.1, gyro_bias_rad_s: 1e-3,
    ///     accel_bias_mps2: 1e-2, star_installation_rad: 1e-2, gyro_scale_factor: 1e-4,
    ///     accel_scale_factor: 1e-4,
    /// };
    /// let config = FilterConfig::without_optional_blocks(FilterMode::ClosedLoop, 3, initial);
    /// let floor_sigma = [1e-2; OptionalBlock::ALL.len()];
    /// // No block in use: every bound zero (never read).
    /// let bounds = OptionalVarianceBounds::new(&floor_sigma, 10.0, &config)?;
    /// assert!(bounds.floor.iter().chain(&bounds.ceiling).all(|bound| *bound == 0.0));
    /// // A ceiling below the prior is refused.
    /// assert!(OptionalVarianceBounds::new(&floor_sigma, 0.5, &config).is_err());
    /// # Ok::<(), nav_core::NavError>(())
    /// ```
    pub fn new(
        floor_sigma: &[f64; OptionalBlock::ALL.len()],
        ceiling_factor: f64,
        config: &FilterConfig,
    ) -> Result<Self, NavError> {
        config.validate()?;
        if !(ceiling_factor.is_finite() && ceiling_factor >= 1.0) {
            return Err(NavError::InvalidConfiguration);
        }
        let mut bounds = Self {
            floor: [0.0; OPTIONAL_DIMENSION],
            ceiling: [0.0; OPTIONAL_DIMENSION],
        };
        let priors = config.optional_prior_variances();
        for (block, sigma) in OptionalBlock::ALL.iter().zip(floor_sigma) {
            if !config.optional_block_in_use(*block) {
                continue;
            }
            if !(sigma.is_finite() && *sigma >= 0.0) {
                return Err(NavError::InvalidConfiguration);
            }
            let states = Self::states(*block);
            let floors = bounds.floor.get_mut(states.clone()).into_iter().flatten();
            let ceilings = bounds.ceiling.get_mut(states.clone()).into_iter().flatten();
            let priors = priors.get(states).into_iter().flatten();
            for ((floor, ceiling), prior) in floors.zip(ceilings).zip(priors) {
                *floor = sigma * sigma;
                *ceiling = prior * (ceiling_factor * ceiling_factor);
            }
        }
        Ok(bounds)
    }
}

impl ErrorStateFilter {
    /// Covariance protection of the optional blocks in use, in place, by the rule of
    /// [`ErrorStateFilter::protect_variances`]: each variance below its floor is raised to
    /// it; each above its ceiling becomes the ceiling with the rest of its row and column of
    /// the whole covariance (the block's own, its cross-covariance with the core states and
    /// with the other optional block) multiplied by `s = √(ceiling/variance)`,
    /// `P' = S P S`, which keeps every correlation coefficient and positive definiteness.
    /// Returns whether anything was changed. Only the diagonal is read unless a bound is
    /// crossed; a block not in use is not read.
    #[inline]
    pub fn protect_optional_variances(&mut self, bounds: &OptionalVarianceBounds) -> bool {
        self.blocks.any_enabled() && self.blocks.protect_variances(bounds)
    }

    /// Freezes the optional `block` (`frozen`) or releases it: while frozen its gain rows are
    /// zero in every update, so its estimate does not move and, the Joseph form being valid
    /// for any gain, `P` stays the exact covariance of the suboptimal update (as a frozen
    /// core block's, [`ErrorStateFilter::update_with_frozen_blocks`]). Its propagation is
    /// unchanged: the model still describes the error. A restart releases every block.
    ///
    /// # Errors
    /// [`NavError::InvalidConfiguration`] if the block is not in use or the layout does not
    /// let it be frozen ([`OptionalBlock::may_freeze`]); nothing changes then.
    pub fn set_optional_block_frozen(
        &mut self,
        block: OptionalBlock,
        frozen: bool,
    ) -> Result<(), NavError> {
        if !(block.may_freeze() && self.blocks.is_enabled(block)) {
            return Err(NavError::InvalidConfiguration);
        }
        self.blocks.set_frozen(block, frozen);
        Ok(())
    }

    /// Whether the optional `block` is in use (compiled in and enabled by the
    /// configuration).
    pub fn optional_block_in_use(&self, block: OptionalBlock) -> bool {
        self.blocks.is_enabled(block)
    }

    /// Whether the optional `block` is frozen ([`Self::set_optional_block_frozen`]).
    pub fn optional_block_frozen(&self, block: OptionalBlock) -> bool {
        self.blocks.is_frozen(block)
    }
}
