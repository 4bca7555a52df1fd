//! The repeat scatter of a damping ratio between nominally identical tests, and the tests
//! of fit that use it (`coil-tune damping`, [`crate::law`]).
//!
//! # Repeat scatter
//! Decay tests repeated on one rig (same spring, attached mass and mode) do not give the
//! same zeta: mounting, amplitude and temperature move it by about 3 % (the paper's
//! Table 1: 0.0017-0.0018 around 0.00175), far more than one record's fit error. When a
//! case holds such repeats, the relative scatter is their pooled estimate
//!
//! ```text
//! s^2 = sum_g sum_i (zeta_gi / mean_g - 1)^2 / nu,     nu = sum_g (n_g - 1)
//! ```
//!
//! over the groups g of n_g >= 2 records taken at one mass in one mode; otherwise a stated
//! default (3 %). The estimate includes each record's fit error, which is then also in the
//! record's own variance: it is counted twice, a negligible excess (the fit error is about
//! 1e-3 of the scatter on the records the tests use).
//!
//! # Tests of fit
//! A law fitted to n records with `f` free parameters (those the non-negative fit did not
//! hold at zero) leaves `dof = n - f`. With the default scatter the weighted chi-square is
//! judged against its 99.9 % point. With a scatter estimated from `nu` repeats, the
//! textbook lack-of-fit test with replicates (Draper and Smith, *Applied Regression
//! Analysis*, 3rd ed., section 2.1): the chi-square splits into the pure error of the
//! repeats around their group means (`chi2_pe`, law-independent, `nu` degrees of freedom)
//! and the lack of fit (`chi2 - chi2_pe`, `dof - nu`), and
//! `F = ((chi2 - chi2_pe) / (dof - nu)) / (chi2_pe / nu)` is judged against the 99.9 %
//! point of F(dof - nu, nu): few repeats give a wide scatter estimate, and F's heavier tail
//! says so. A law with as many free parameters as distinct tests (`dof - nu <= 0`) is
//! exactly determined: it cannot miss, and is judged by its parameters' admissibility
//! (none held at zero by the non-negative fit; a held one is a degree of freedom the test
//! counts).
//!
//! Quantiles by bisection on the distribution functions: chi-square's the regularised
//! incomplete gamma function `P(dof / 2, x / 2)` (series and continued fraction, Numerical
//! Recipes 3rd ed. section 6.2), F's the regularised incomplete beta function
//! `P(F <= x) = I_{d1 x / (d1 x + d2)}(d1 / 2, d2 / 2)` (continued fraction, Numerical
//! Recipes 3rd ed. section 6.4; ln Gamma by Lanczos, g = 7).

use serde::Serialize;

/// How many fit errors a group's mean zeta must stand above zero to enter the scatter
/// estimate.
pub const MEASURED_ZETA: f64 = 10.0;

/// Where the scatter used came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ScatterSource {
    /// Estimated from repeated tests in the case.
    Repeats,
    /// The stated default (no repeats in the case).
    Default,
}

/// The repeat scatter of one test's zeta, as used by the fit and its tests.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RepeatScatter {
    /// Relative 1-sigma scatter of one test's zeta (-).
    pub relative: f64,
    /// Where it came from.
    pub source: ScatterSource,
    /// Degrees of freedom of the estimate (records minus groups; 0 for the default).
    pub dof: usize,
    /// The default that applies without repeats (relative).
    pub default: f64,
    /// The groups of repeated tests, by record name.
    pub groups: Vec<Vec<String>>,
    /// The same groups by record index (not serialised).
    #[serde(skip)]
    pub members: Vec<Vec<usize>>,
}

impl RepeatScatter {
    /// The default scatter, no repeats.
    pub fn stated(default: f64) -> Self {
        RepeatScatter {
            relative: default,
            source: ScatterSource::Default,
            dof: 0,
            default,
            groups: Vec::new(),
            members: Vec::new(),
        }
    }

    /// Pools the relative spread of `zeta` within each group of `members` (indices into
    /// `zeta`); `se` are the records' fit errors, `names` their labels. A group counts
    /// when it has at least two records and its mean stands [`MEASURED_ZETA`] fit errors
    /// above zero (the relative spread of a zeta that is zero within its error, such as a
    /// surge mode no law damps, is not a scatter). Without such a group, or when the
    /// spread is zero, the stated `default` applies.
    pub fn estimate(
        zeta: &[f64],
        se: &[f64],
        members: &[Vec<usize>],
        names: &[String],
        default: f64,
    ) -> Self {
        let mut sum = 0.0;
        let mut dof = 0;
        let mut used = Vec::new();
        for g in members {
            let mean = g.iter().map(|&i| zeta[i]).sum::<f64>() / g.len() as f64;
            let largest_se = g.iter().map(|&i| se[i]).fold(0.0, f64::max);
            if g.len() < 2 || !(mean.is_finite() && mean > MEASURED_ZETA * largest_se) {
                continue;
            }
            sum += g
                .iter()
                .map(|&i| (zeta[i] / mean - 1.0).powi(2))
                .sum::<f64>();
            dof += g.len() - 1;
            used.push(g.clone());
        }
        if dof == 0 || !(sum > 0.0 && sum.is_finite()) {
            return Self::stated(default);
        }
        RepeatScatter {
            relative: (sum / dof as f64).sqrt(),
            source: ScatterSource::Repeats,
            dof,
            default,
            groups: used
                .iter()
                .map(|g| g.iter().map(|&i| names[i].clone()).collect())
                .collect(),
            members: used,
        }
    }

    /// `relative` in words, with its source.
    pub fn text(&self) -> String {
        match self.source {
            ScatterSource::Repeats => format!(
                "{:.2} % (estimated from {} repeated test(s) in {} group(s), {} degree(s) of freedom)",
                100.0 * self.relative,
                self.groups.iter().map(Vec::len).sum::<usize>(),
                self.groups.len(),
                self.dof
            ),
            ScatterSource::Default => format!(
                "{:.2} % (the stated default: the case has no repeated test)",
                100.0 * self.relative
            ),
        }
    }

    /// The weighted pure-error chi-square of the repeats around their group means, with
    /// weights `w` per record.
    pub fn pure_error(&self, zeta: &[f64], w: &[f64]) -> f64 {
        self.members
            .iter()
            .map(|g| {
                let sw: f64 = g.iter().map(|&i| w[i]).sum();
                let mean = g.iter().map(|&i| w[i] * zeta[i]).sum::<f64>() / sw;
                g.iter()
                    .map(|&i| w[i] * (zeta[i] - mean).powi(2))
                    .sum::<f64>()
            })
            .sum()
    }

    /// Judges a fit with weighted `chi2` on `dof` degrees of freedom whose records hold
    /// the pure error `pure` (module docs).
    pub fn judge(&self, chi2: f64, dof: usize, pure: f64) -> FitTest {
        if self.dof == 0 || pure <= 0.0 {
            return FitTest {
                statistic: chi2,
                critical: chi2_999(dof),
                dof,
                consistent: dof == 0 || chi2 <= chi2_999(dof),
            };
        }
        let lack_dof = dof.saturating_sub(self.dof);
        if lack_dof == 0 {
            return FitTest {
                statistic: 0.0,
                critical: 0.0,
                dof: 0,
                consistent: true,
            };
        }
        let f = ((chi2 - pure).max(0.0) / lack_dof as f64) / (pure / self.dof as f64);
        let critical = f_quantile(0.999, lack_dof as f64, self.dof as f64);
        FitTest {
            statistic: f,
            critical,
            dof: lack_dof,
            consistent: f <= critical,
        }
    }

    /// Factor on a held-out score's threshold: the 99.9 % point of F(1, nu) over that of
    /// chi-square(1) when the scatter is estimated, 1 otherwise.
    pub fn held_out_factor(&self) -> f64 {
        if self.dof == 0 {
            1.0
        } else {
            f_quantile(0.999, 1.0, self.dof as f64) / chi2_999(1)
        }
    }
}

/// A test of fit: the statistic against its 99.9 % point.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct FitTest {
    /// chi2 (default scatter) or the lack-of-fit F (estimated scatter).
    pub statistic: f64,
    /// Its 99.9 % point (0 when the law is exactly determined).
    pub critical: f64,
    /// Degrees of freedom of the statistic (the numerator's for F).
    pub dof: usize,
    /// Statistic at most the critical value (or exactly determined).
    pub consistent: bool,
}

/// The 99.9 % point of chi-square with `dof` degrees of freedom (0 for none).
pub fn chi2_999(dof: usize) -> f64 {
    if dof == 0 {
        return 0.0;
    }
    let a = dof as f64 / 2.0;
    2.0 * bisect(|x| incomplete_gamma(a, x) < 0.999)
}

/// The regularised lower incomplete gamma function `P(a, x)` (series below `a + 1`,
/// continued fraction above; Numerical Recipes 3rd ed. section 6.2).
fn incomplete_gamma(a: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 0.0;
    }
    let front = (a * x.ln() - x - ln_gamma(a)).exp();
    if x < a + 1.0 {
        let (mut term, mut sum, mut ap) = (1.0 / a, 1.0 / a, a);
        for _ in 0..500 {
            ap += 1.0;
            term *= x / ap;
            sum += term;
            if term.abs() < sum.abs() * 1e-16 {
                break;
            }
        }
        front * sum
    } else {
        let tiny = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / tiny;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..500 {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            if d.abs() < tiny {
                d = tiny;
            }
            c = b + an / c;
            if c.abs() < tiny {
                c = tiny;
            }
            d = 1.0 / d;
            h *= d * c;
            if (d * c - 1.0).abs() < 1e-16 {
                break;
            }
        }
        1.0 - front * h
    }
}

/// The x > 0 where `below(x)` turns false (bisection on ln x over e^-30 .. e^30).
fn bisect(below: impl Fn(f64) -> bool) -> f64 {
    let (mut lo, mut hi) = (-30.0f64, 30.0f64);
    while hi - lo > 1e-12 {
        let mid = 0.5 * (lo + hi);
        if below(mid.exp()) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    (0.5 * (lo + hi)).exp()
}

/// ln Gamma(x) for x > 0 (Lanczos, g = 7, 9 terms; relative error below 1e-13).
fn ln_gamma(x: f64) -> f64 {
    const C: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    if x < 0.5 {
        // Reflection: Gamma(x) Gamma(1 - x) = pi / sin(pi x).
        return (std::f64::consts::PI / (std::f64::consts::PI * x).sin()).ln() - ln_gamma(1.0 - x);
    }
    let x = x - 1.0;
    let mut a = C[0];
    let t = x + 7.5;
    for (i, &c) in C.iter().enumerate().skip(1) {
        a += c / (x + i as f64);
    }
    0.5 * (2.0 * std::f64::consts::PI).ln() + (x + 0.5) * t.ln() - t + a.ln()
}

/// The continued fraction of the incomplete beta function (modified Lentz).
fn beta_fraction(a: f64, b: f64, x: f64) -> f64 {
    let tiny = 1e-300;
    let (qab, qap, qam) = (a + b, a + 1.0, a - 1.0);
    let mut c = 1.0;
    let mut d = 1.0 - qab * x / qap;
    if d.abs() < tiny {
        d = tiny;
    }
    d = 1.0 / d;
    let mut h = d;
    for m in 1..=300 {
        let m = m as f64;
        let m2 = 2.0 * m;
        for aa in [
            m * (b - m) * x / ((qam + m2) * (a + m2)),
            -(a + m) * (qab + m) * x / ((a + m2) * (qap + m2)),
        ] {
            d = 1.0 + aa * d;
            if d.abs() < tiny {
                d = tiny;
            }
            c = 1.0 + aa / c;
            if c.abs() < tiny {
                c = tiny;
            }
            d = 1.0 / d;
            h *= d * c;
        }
        if (d * c - 1.0).abs() < 1e-15 {
            break;
        }
    }
    h
}

/// The regularised incomplete beta function `I_x(a, b)`.
fn incomplete_beta(a: f64, b: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 0.0;
    }
    if x >= 1.0 {
        return 1.0;
    }
    let front =
        (ln_gamma(a + b) - ln_gamma(a) - ln_gamma(b) + a * x.ln() + b * (1.0 - x).ln()).exp();
    if x < (a + 1.0) / (a + b + 2.0) {
        front * beta_fraction(a, b, x) / a
    } else {
        1.0 - front * beta_fraction(b, a, 1.0 - x) / b
    }
}

/// `P(F <= x)` for F with `d1` and `d2` degrees of freedom.
fn f_cdf(x: f64, d1: f64, d2: f64) -> f64 {
    if x <= 0.0 {
        return 0.0;
    }
    incomplete_beta(d1 / 2.0, d2 / 2.0, d1 * x / (d1 * x + d2))
}

/// The `p` quantile of F with `d1` and `d2` degrees of freedom.
pub fn f_quantile(p: f64, d1: f64, d2: f64) -> f64 {
    bisect(|x| f_cdf(x, d1, d2) < p)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// F quantiles against printed tables (Abramowitz and Stegun 26.6; R's qf).
    #[test]
    fn f_quantiles_match_the_tables() {
        for (p, d1, d2, want) in [
            (0.95, 3.0, 10.0, 3.708_265),
            (0.999, 1.0, 4.0, 74.137_4),
            (0.999, 2.0, 10.0, 14.905_4),
            (0.999, 1.0, 1.0, 405_284.1),
            (0.5, 4.0, 4.0, 1.0),
        ] {
            let got = f_quantile(p, d1, d2);
            assert!(
                (got / want - 1.0).abs() < 1e-4,
                "F({p}; {d1}, {d2}) = {got}, want {want}"
            );
        }
        // Chi-square's 99.9 % points (tables), and F(1, nu) tending to chi-square(1).
        for (dof, want) in [(1, 10.828), (2, 13.816), (5, 20.515), (30, 59.703)] {
            assert!(
                (chi2_999(dof) / want - 1.0).abs() < 1e-4,
                "{dof}: {}",
                chi2_999(dof)
            );
        }
        assert!((f_quantile(0.999, 1.0, 1e6) / 10.828 - 1.0).abs() < 2e-3);
    }

    #[test]
    fn pooled_scatter_and_lack_of_fit() {
        // Two groups of three at 3 % apart-ish, one singleton.
        let zeta = [1.0, 1.03, 0.97, 2.0, 2.06, 1.94, 5.0];
        let names: Vec<String> = (0..7).map(|i| format!("r{i}")).collect();
        let se = [1e-4; 7];
        let s = RepeatScatter::estimate(
            &zeta,
            &se,
            &[vec![0, 1, 2], vec![3, 4, 5], vec![6]],
            &names,
            0.03,
        );
        assert_eq!(s.source, ScatterSource::Repeats);
        assert_eq!(s.dof, 4);
        // Each group: deviations +-3 %, sum of squares 2 * 9e-4 per group.
        assert!((s.relative - (4.0 * 9e-4 / 4.0f64).sqrt()).abs() < 1e-12);
        // Exactly determined at the group level: consistent whatever chi2.
        assert!(s.judge(1e6, 4, 4.0).consistent);
        // Lack of fit 100 on 1 dof against pure error 4 on 4: F = 100 > F(1, 4) 74.1.
        assert!(!s.judge(104.0, 5, 4.0).consistent);
        assert!(s.judge(60.0, 5, 4.0).consistent);
        // No repeats: the default, chi-square.
        let d = RepeatScatter::estimate(&zeta, &se, &[vec![0], vec![1]], &names, 0.03);
        // A group whose zeta is zero within its fit errors does not enter the estimate.
        let z0 = [1e-7, 5e-7, -3e-7, 1.0, 1.03];
        let groups = [vec![0, 1, 2], vec![3, 4]];
        let e = RepeatScatter::estimate(&z0, &[1e-6; 5], &groups, &names, 0.03);
        assert_eq!((e.dof, e.groups.len()), (1, 1));
        assert_eq!((d.source, d.relative), (ScatterSource::Default, 0.03));
        assert!(!d.judge(11.0, 1, 0.0).consistent && d.judge(10.0, 1, 0.0).consistent);
    }
}
