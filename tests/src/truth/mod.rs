//! An independent truth model that writes measured-style cases
//! (`docs/measured-case.md`) with a hidden physical effect, so that tests can check
//! that `coil-tune diagnose` finds it. Nothing here uses coil's FE solver, mesher, tuner or
//! post-processor: the stiffness is a closed form and the integrator is written here, so
//! agreement between diagnose and this truth is evidence, not a tautology.
//!
//! # Spring: closed-form compliance of the helix
//! Wahl, *Mechanical Springs* (2nd ed., 1963), ch. 17 ("Helical springs under axial load
//! and twisting moment"); also Timoshenko, *Strength of Materials* II. With R = D/2, the
//! pitch angle `a = atan(h / (pi D))`, the wire length `L = n pi D / cos a`, the wire's
//! `A = pi d^2/4`, `I = pi d^4/64`, `J = 2I` and `G = E / (2 (1 + nu))`, an axial force F
//! and an axial moment M at the end load a wire section with the torque
//! `T = F R cos a + M sin a`, the bending moment `Mb = M cos a - F R sin a`, the shear
//! force `F cos a` and the axial force `F sin a`. Castigliano's theorem on
//! `U = L/2 [T^2/GJ + Mb^2/EI + (F cos a)^2/(kappa G A) + (F sin a)^2/EA]` gives the
//! compliance `(delta, phi) = C (F, M)`:
//! ```text
//! C_zz = L [R^2 cos^2 a / GJ + R^2 sin^2 a / EI + cos^2 a / (kappa G A) + sin^2 a / EA]
//! C_zt = L R sin a cos a (1/GJ - 1/EI)
//! C_tt = L [sin^2 a / GJ + cos^2 a / EI]
//! ```
//! with Cowper's shear coefficient of a solid circle `kappa = 6 (1 + nu) / (7 + 6 nu)`.
//! Signs: delta is the extension along the axis (away from the base), phi the end
//! rotation about that axis, right-handed, for a helix winding right-handed as it rises;
//! the other hand flips C_zt, which no frequency sees (only C_zt^2 enters).
//!
//! # Dynamics: a lumped chain
//! The spring is a chain of N equal segments, node 0 clamped at the base, node N the top
//! end carrying the weight. DOFs per node: (u, theta), u the axial displacement (m,
//! positive away from the base), theta the rotation about the axis (rad). Each segment has
//! the stiffness `K_s = N C^-1` (N m^-1, N, N m). Masses: the wire's mass
//! `m_s = rho A L` is lumped in equal shares m_s/N (half shares at the ends; the base's is
//! lost to the clamp), its rotary inertia as rings, `m_node R^2`. The weight (mass m) sits
//! on node N; its rotation is either held (a guide: theta_N = 0) or free with the rotary
//! inertia J (`axial_torsional_coupling`). Damping: stiffness-proportional `beta K_s` on
//! every segment, `beta = 2 zeta / w_ax`, w_ax the chain's axial mode with the weight's
//! rotation held, so that mode's damping ratio is exactly `zeta` (a Rayleigh family with
//! alpha = 0, which the paper's model can match). Gravity `g` acts on the weight only (the
//! spring's self-weight would add about m_s/(2m) to the preload; the spec's model does
//! not have it either).
//!
//! # Effects at the weight (the spec's table)
//! `coulomb_friction` F opposing the weight's axial velocity, sticking while the other
//! forces stay within F; `quadratic_damping` `-c2 v|v|`; `cubic_stiffness` `k3 x^3` in
//! parallel with the spring, x the compression from the free length (so the gravity
//! preload solves `k x + k3 x^3 = m g`); `axial_torsional_coupling` frees the weight's
//! rotation with rotary inertia J.
//!
//! # Integrator
//! Explicit leapfrog (kick-drift, the central-difference scheme on lumped masses):
//! `v_{n+1/2} = v_{n-1/2} + dt a_n`, `u_{n+1} = u_n + dt v_{n+1/2}`, the velocity-dependent
//! forces evaluated with `v_{n-1/2}` (a half-step lag acts, to first order, as a tiny
//! stiffness change; the dissipation is second-order accurate). Stability of the damped
//! scheme needs `w^2 dt (dt + 2 beta) < 4` for every chain mode; dt is half of that limit
//! for the chain's highest mode (from its eigenvalues) and divides the sample period in
//! an odd number of steps. Friction (a standard explicit stick-slip treatment): a sliding
//! weight whose velocity would reverse within a step sticks (v = 0) if the other forces
//! are within F, else it reverses and slides the rest of the step with the opposite
//! friction; a stuck weight breaks free when the other forces exceed F. The recorded
//! acceleration is the weight's force balance at each step (not a difference).
//!
//! # Measurement model
//! The simulation starts at the static equilibrium (gravity) with an impulse (an initial
//! axial velocity of the weight). A random lead (0.2-1.2 s, a random start phase) is cut
//! off, the fine acceleration is averaged over one sample period centred on each sample
//! time (a simple anti-alias filter: its gain at the axial mode is `1 - (pi f/fs)^2/6`,
//! under 3e-4 here), the record's mean is removed (AC coupling: DC only), Gaussian noise of
//! a given fraction of the peak is added and the result quantised to 16 bits over
//! +-1.2 x peak. The random numbers come from xoshiro256** seeded by splitmix64 (Blackman
//! and Vigna, 2018) with Box-Muller normals, so every case is reproducible bit for bit.
//! The static record is quasi-static: compression from 0 to the compression under
//! 1.5 m g (with g = 9.81 when the case has no gravity) and back, the force
//! `k x + k3 x^3` plus the friction on loading and minus it on unloading, with the same end
//! condition as the dynamics, and noise on both columns.
//!
//! Units: SI inside (m, N, kg, s, rad); the files carry the spec's units (mm, N, MPa).
//!
//! [`model`]: the spring, its effects and the chain integrated here; [`record`]: the
//! records and files a case is written as; [`cases`]: the catalogue of cases; [`loss`]:
//! the damping classes the records show and the laws outside the catalogue.

pub mod cases;
pub mod loss;
pub mod model;
pub mod record;

pub use cases::*;
pub use model::*;
pub use record::*;
