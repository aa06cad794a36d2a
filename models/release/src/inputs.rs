//! The explicit inputs of one release (plain numbers) and the nominal values of physics.md.

use crate::expgauss::ExpGauss;
use crate::integrator::{DormandPrince, IntegrateError, Integrator};
use crate::model::{ReleaseModel, ReleaseOutcome};
use geodesic_contact::{ExponentialAdhesion, Hertz, HertzAdhesion};
use geodesic_mechanism::{PiezoMechanism, PiezoParams, VoltageCommand};

/// TM mass `M` [kg] (thesis ch. 6).
pub const TM_MASS_KG: f64 = 1.96;
/// Nominal preload `F0` [N].
pub const PRELOAD_NOMINAL_N: f64 = 0.300;

/// Every input of one in-flight release; index 0 is mechanism/contact 1 (at -X), 1 is 2.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReleaseInputs {
    /// Mechanism parameters.
    pub mech: [PiezoParams; 2],
    /// Voltage discharge slopes `em` [V/s].
    pub em_v_s: [f64; 2],
    /// Initial command voltage [V].
    pub e0_v: f64,
    /// Tip radii [m].
    pub tip_radius_m: [f64; 2],
    /// Effective modulus `E*` [Pa].
    pub e_star_pa: f64,
    /// Preload `F0` [N].
    pub preload_n: f64,
    /// Adhesion stiffness `A1` [N/m].
    pub a1_n_m: [f64; 2],
    /// Adhesion length `lambda` [m].
    pub lambda_m: [f64; 2],
    /// TM mass [kg].
    pub tm_mass_kg: f64,
}

impl ReleaseInputs {
    /// Nominal mechanisms, slopes, radii and preload, no adhesion (physics.md §1-3).
    pub fn nominal() -> Self {
        Self {
            mech: [PiezoParams::nominal(); 2],
            em_v_s: [VoltageCommand::SLOPE_NOMINAL_V_S; 2],
            e0_v: VoltageCommand::E0_NOMINAL_V,
            tip_radius_m: [Hertz::RADIUS_NOMINAL_M; 2],
            e_star_pa: Hertz::E_STAR_NOMINAL_PA,
            preload_n: PRELOAD_NOMINAL_N,
            a1_n_m: [0.0; 2],
            lambda_m: [0.0; 2],
            tm_mass_kg: TM_MASS_KG,
        }
    }

    /// Builds the simulator model.
    pub fn model(&self) -> ReleaseModel<PiezoMechanism, HertzAdhesion> {
        let mech = |i: usize| {
            PiezoMechanism::new(
                self.mech[i],
                VoltageCommand::ramp(self.e0_v, self.em_v_s[i]),
            )
        };
        let contact = |i: usize| {
            HertzAdhesion::new(
                Hertz::new(self.e_star_pa, self.tip_radius_m[i]),
                ExponentialAdhesion::new(self.a1_n_m[i], self.lambda_m[i]),
            )
        };
        ReleaseModel::new(
            [mech(0), mech(1)],
            [contact(0), contact(1)],
            self.tm_mass_kg,
            self.preload_n,
        )
    }

    /// Simulates the release with the exponential Gauss collocation (the Monte Carlo's
    /// integrator; the piezo mechanism always gives its modes, Dormand-Prince
    /// ([`DormandPrince::fast`]) takes over only if a modal decomposition failed).
    pub fn simulate_fast(&self, cfg: &ExpGauss) -> Result<ReleaseOutcome, IntegrateError> {
        let model = self.model();
        match model.simulate_expgauss(cfg) {
            Some(r) => r,
            None => model.simulate(&DormandPrince::fast()),
        }
    }

    /// Simulates the release.
    pub fn simulate<I: Integrator>(
        &self,
        integrator: &I,
    ) -> Result<ReleaseOutcome, IntegrateError> {
        self.model().simulate(integrator)
    }
}
