use coil_tests::truth::*;
fn main() {
    for c in extended_cases() {
        let t0 = std::time::Instant::now();
        let g = generate(&c);
        let p = axial_mode(&c).unwrap().omega.recip() * std::f64::consts::TAU;
        let a = c.impulse_velocity_m_s * p / std::f64::consts::TAU;
        let x0 = c.equilibrium_compression_m();
        println!("{:28} T {:.3} cyc {:5.0} n {:6} shift {:+.4} causes {:?} peak {:.3e} lsb {:.2e} x0+A/lim {:.2} start {} {:.2}s",
            c.name, p, c.record_s / p, g.decay.len(), backbone_shift(&c), c.causes(), g.peak_m_s2, g.quantisation_m_s2,
            (x0 + a) / c.softening_limit_m(), g.free_decay_start, t0.elapsed().as_secs_f64());
    }
}
