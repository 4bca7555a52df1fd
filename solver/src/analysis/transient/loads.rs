//! The load of a transient case on the free DOFs, `f(t) = f_c + sum_k s_k(t) f_k`: the
//! constant pattern and one pattern per table (the "Loads" section of [`super`]).

use crate::analysis::system::{interpolate, table_points, System};
use crate::error::solve::SolveError;
use crate::model::{LoadCase, PointLoad};

/// The free-DOF load `f(t) = f_c + sum_k s_k(t) f_k`: a constant pattern (untabled loads
/// and the prescribed-displacement load) and one pattern per table.
pub(super) struct LoadPatterns {
    pub(super) constant: Vec<f64>,
    pub(super) tabled: Vec<TabledLoad>,
}

pub(super) struct TabledLoad {
    pub(super) table: String,
    pub(super) points: Vec<(f64, f64)>,
    pub(super) load: Vec<f64>,
}

impl LoadPatterns {
    pub(super) fn new(system: &System, case: &LoadCase) -> Result<Self, SolveError> {
        let model = system.model;
        let all: Vec<&PointLoad> = model.point_loads.iter().chain(&case.point_loads).collect();
        let untabled = all.iter().copied().filter(|l| l.table.is_none());
        let constant = system.free_load(&system.point_load_vector(untabled, 0.0)?);
        let mut names: Vec<&str> = all.iter().filter_map(|l| l.table.as_deref()).collect();
        names.sort_unstable_by_key(|n| n.to_ascii_lowercase());
        names.dedup_by(|a, b| a.eq_ignore_ascii_case(b));
        let mut tabled = Vec::with_capacity(names.len());
        for name in names {
            let points = table_points(model, name)?.to_vec();
            // The table's own spelling, for messages.
            let table = model
                .tables
                .iter()
                .find(|t| t.name.eq_ignore_ascii_case(name))
                .map_or(name, |t| t.name.as_str());
            let loads: Vec<PointLoad> = all
                .iter()
                .filter(|l| {
                    l.table
                        .as_deref()
                        .is_some_and(|t| t.eq_ignore_ascii_case(name))
                })
                .map(|l| PointLoad {
                    table: None,
                    ..(*l).clone()
                })
                .collect();
            let f_full = system.point_load_vector(&loads, 0.0)?;
            let mut load = vec![0.0; system.dim()];
            system.dofs.restrict_add(&f_full, &mut load);
            tabled.push(TabledLoad {
                table: table.to_string(),
                points,
                load,
            });
        }
        Ok(LoadPatterns { constant, tabled })
    }

    /// Every pattern with its time factor function.
    pub(super) fn patterns(&self) -> impl Iterator<Item = &[f64]> {
        std::iter::once(self.constant.as_slice()).chain(self.tabled.iter().map(|t| &t.load[..]))
    }

    /// The factor of each pattern at `t` (1 for the constant one).
    pub(super) fn factors(&self, t: f64, out: &mut [f64]) {
        out[0] = 1.0;
        for (o, tabled) in out[1..].iter_mut().zip(&self.tabled) {
            *o = interpolate(&tabled.points, t);
        }
    }

    pub(super) fn count(&self) -> usize {
        1 + self.tabled.len()
    }

    /// Warns about table breakpoints inside the run that are not on the step grid: the
    /// load is sampled at the steps and taken linear in between.
    pub(super) fn check_grid(&self, dt: f64, steps: usize, warnings: &mut Vec<String>) {
        let end = steps as f64 * dt;
        for tabled in &self.tabled {
            let off: Vec<f64> = tabled
                .points
                .iter()
                .map(|p| p.0)
                .filter(|&t| t > 0.0 && t < end && ((t / dt) - (t / dt).round()).abs() > 1e-6)
                .collect();
            if let Some(first) = off.first() {
                warnings.push(format!(
                    "table '{}' has {} breakpoint(s) between steps of {dt} s (first at {first} s): \
                     the load is sampled at the steps and taken linear in between, so a feature \
                     shorter than a step is misrepresented; put breakpoints on multiples of dt",
                    tabled.table,
                    off.len()
                ));
            }
        }
    }
}
