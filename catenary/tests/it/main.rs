//! coil-catenary's integration tests (one binary): the mean contact force against its
//! closed form on a short catenary, the reference case against its ranges (ignored: long)
//! (the command itself: `cli/tests/it/catenary_cli.rs`).

mod closed_form;
mod reference_case;

use coil_mesher::catenary::{
    CatenarySpec, DampingSpec, DropperSpec, PantographSpec, StageSpec, SupportSpec, WireSpec,
};

/// Two 60 m spans of the EN 50318 reference wires and droppers, 1 m elements.
pub fn short_catenary() -> CatenarySpec {
    CatenarySpec {
        spans: 2,
        span_length_m: 60.0,
        system_height_m: 1.2,
        presag_mm: 0.0,
        contact_wire: WireSpec {
            mass_kg_m: 1.35,
            tension_n: 20_000.0,
            ei_n_m2: 195.0,
        },
        messenger_wire: WireSpec {
            mass_kg_m: 1.07,
            tension_n: 16_000.0,
            ei_n_m2: 131.7,
        },
        droppers: DropperSpec {
            positions_m: vec![5.0, 10.5, 17.0, 23.5, 30.0, 36.5, 43.0, 49.5, 55.0],
            stiffness_n_m: 100_000.0,
            contact_clamp_mass_kg: 0.195,
            messenger_clamp_mass_kg: 0.165,
        },
        steady_arm: SupportSpec {
            stiffness_n_m: 300.0,
            mass_kg: 1.0,
        },
        messenger_support: SupportSpec {
            stiffness_n_m: 50_000.0,
            mass_kg: 0.0,
        },
        damping: DampingSpec {
            ratio: 0.005,
            frequencies_hz: [1.0, 20.0],
        },
        element_length_m: 1.0,
        gravity_m_s2: 9.81,
    }
}

/// The EN 50318 two-stage pantograph with a 120 N uplift.
pub fn pantograph() -> PantographSpec {
    PantographSpec {
        stages: vec![
            StageSpec {
                mass_kg: 7.2,
                stiffness_n_m: 4200.0,
                damping_n_s_m: 10.0,
            },
            StageSpec {
                mass_kg: 15.0,
                stiffness_n_m: 50.0,
                damping_n_s_m: 90.0,
            },
        ],
        uplift_force_n: 120.0,
        contact_stiffness_n_m: 50_000.0,
    }
}
