//! Recording a transient's history: which node DOFs and quantities are written, the
//! sampling every `g`-th step, the column names and SI units (the "Output" section of
//! [`super`]).

use crate::analysis::system::System;
use crate::dof::dof_name;
use crate::error::solve::SolveError;
use crate::model::{units, Quantity};
use faer::Mat;
use std::fmt::Write as _;

/// Most values (rows times columns) a history may hold (800 MB in memory).
pub const MAX_HISTORY_VALUES: usize = 100_000_000;

/// One recorded signal.
#[derive(Debug, Clone, PartialEq)]
pub struct HistoryColumn {
    /// `node{ID}_{dof}_{quantity}_{unit}`, e.g. `node1_uz_accel_m_s2`.
    pub name: String,
    /// Values in the SI unit the name carries.
    pub values: Vec<f64>,
}

/// The recorded signals of a transient case.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct History {
    /// Sample times (s), `k dt` for the recorded steps `k`.
    pub time_s: Vec<f64>,
    /// One column per recorded signal, in header order.
    pub columns: Vec<HistoryColumn>,
}

impl History {
    /// The values of a column.
    pub fn column(&self, name: &str) -> Option<&[f64]> {
        self.columns
            .iter()
            .find(|c| c.name == name)
            .map(|c| c.values.as_slice())
    }

    /// The column names, in order.
    pub fn names(&self) -> Vec<String> {
        self.columns.iter().map(|c| c.name.clone()).collect()
    }

    /// CSV text: a header `time_s,name,...` and one row per sample. Times print in
    /// plain decimal, values in scientific notation; both are the shortest text that
    /// reads back to the same `f64`.
    pub fn to_csv(&self) -> String {
        let mut out = String::with_capacity(24 * (self.columns.len() + 1) * self.time_s.len());
        out.push_str("time_s");
        for c in &self.columns {
            out.push(',');
            out.push_str(&c.name);
        }
        out.push('\n');
        for (row, t) in self.time_s.iter().enumerate() {
            // Writing to a String cannot fail.
            let _ = write!(out, "{t}");
            for c in &self.columns {
                let _ = write!(out, ",{:e}", c.values[row]);
            }
            out.push('\n');
        }
        out
    }
}

/// One output DOF: its row of `T` and its prescribed part.
pub(super) struct OutputDof {
    pub(super) terms: Vec<(usize, f64)>,
    pub(super) prescribed: f64,
}

pub(super) struct OutputColumn {
    pub(super) name: String,
    pub(super) slot: usize,
    pub(super) quantity: Quantity,
    /// Model units to SI (mm -> m for translations, 1 for rotations).
    pub(super) scale: f64,
}

/// Collects the requested signals every `every`-th step.
pub(super) struct Recorder {
    pub(super) every: usize,
    pub(super) dofs: Vec<OutputDof>,
    pub(super) columns: Vec<OutputColumn>,
    pub(super) time: Vec<f64>,
    pub(super) values: Vec<Vec<f64>>,
    pub(super) scratch: [Vec<f64>; 3],
    /// Columns the run computes itself: each `MOVING CONTACT`'s force,
    /// `contact{i}_force_n` (i from 1, N), recorded by the direct path at the same rows.
    pub(super) extras: Vec<HistoryColumn>,
}

impl Recorder {
    pub(super) fn new(
        system: &System,
        steps: usize,
        warnings: &mut Vec<String>,
    ) -> Result<Self, SolveError> {
        let model = system.model;
        let mut every = 0usize;
        let mut slots: Vec<usize> = Vec::new();
        let mut dofs = Vec::new();
        let mut columns: Vec<OutputColumn> = Vec::new();
        for request in &model.outputs {
            if request.every == 0 {
                return Err(SolveError::BadInput {
                    what: "HISTORY OUTPUT every 0 steps; expected k >= 1".to_string(),
                });
            }
            every = gcd(every, request.every as usize);
            for &node in &request.nodes {
                for &dof in &request.dofs {
                    let full = system.full_dof(node, dof, "HISTORY OUTPUT")?;
                    let slot = match slots.iter().position(|&d| d == full) {
                        Some(s) => s,
                        None => {
                            slots.push(full);
                            dofs.push(OutputDof {
                                terms: system.dofs.expansion(full).collect(),
                                prescribed: system.dofs.prescribed_part(full),
                            });
                            slots.len() - 1
                        }
                    };
                    for &quantity in &request.quantities {
                        let name = column_name(node, dof, quantity);
                        if columns.iter().any(|c| c.name == name) {
                            continue;
                        }
                        columns.push(OutputColumn {
                            name,
                            slot,
                            quantity,
                            scale: if dof <= 3 { 1.0 / units::MM_PER_M } else { 1.0 },
                        });
                    }
                }
            }
        }
        if columns.is_empty() {
            warnings.push(
                "no HISTORY OUTPUT request: the history holds only the time column".to_string(),
            );
        }
        let every = every.max(1);
        let rows = steps / every + 1;
        if rows.saturating_mul(columns.len() + 1) > MAX_HISTORY_VALUES {
            return Err(SolveError::BadInput {
                what: format!(
                    "the history would hold {rows} rows of {} columns; record every k-th step \
                     with a larger k (HISTORY OUTPUT)",
                    columns.len() + 1
                ),
            });
        }
        let n_slots = dofs.len();
        let extras = (1..=model.moving_contacts().len())
            .map(|i| HistoryColumn {
                name: format!("contact{i}_force_n"),
                values: Vec::with_capacity(rows),
            })
            .collect();
        Ok(Recorder {
            extras,
            every,
            dofs,
            values: columns.iter().map(|_| Vec::with_capacity(rows)).collect(),
            columns,
            time: Vec::with_capacity(rows),
            scratch: [vec![0.0; n_slots], vec![0.0; n_slots], vec![0.0; n_slots]],
        })
    }

    /// The free DOFs whose modal shape rows the outputs need are the `terms`; this gives
    /// the rows of `T Phi` for the output slots.
    pub(super) fn slot_rows(&self, shapes: &Mat<f64>) -> Mat<f64> {
        Mat::from_fn(self.dofs.len(), shapes.ncols(), |slot, mode| {
            self.dofs[slot]
                .terms
                .iter()
                .map(|&(eq, c)| c * shapes[(eq, mode)])
                .sum()
        })
    }

    pub(super) fn wants(&self, step: usize) -> bool {
        step % self.every == 0
    }

    /// Records from free-DOF vectors (direct integration).
    pub(super) fn record_free(&mut self, t: f64, u: &[f64], v: &[f64], a: &[f64]) {
        let [su, sv, sa] = &mut self.scratch;
        for (slot, dof) in self.dofs.iter().enumerate() {
            let (mut x, mut y, mut z) = (0.0, 0.0, 0.0);
            for &(eq, c) in &dof.terms {
                x += c * u[eq];
                y += c * v[eq];
                z += c * a[eq];
            }
            su[slot] = x;
            sv[slot] = y;
            sa[slot] = z;
        }
        let scratch = std::mem::take(&mut self.scratch);
        self.record_slots(t, &scratch[0], &scratch[1], &scratch[2]);
        self.scratch = scratch;
    }

    /// Records from values at the output slots without their prescribed part.
    pub(super) fn record_slots(&mut self, t: f64, u: &[f64], v: &[f64], a: &[f64]) {
        self.time.push(t);
        for (column, values) in self.columns.iter().zip(&mut self.values) {
            let s = column.slot;
            let x = match column.quantity {
                Quantity::Displacement => u[s] + self.dofs[s].prescribed,
                Quantity::Velocity => v[s],
                Quantity::Acceleration => a[s],
            };
            values.push(x * column.scale);
        }
    }

    pub(super) fn finish(self) -> History {
        History {
            time_s: self.time,
            columns: self
                .columns
                .into_iter()
                .zip(self.values)
                .map(|(c, values)| HistoryColumn {
                    name: c.name,
                    values,
                })
                .chain(self.extras)
                .collect(),
        }
    }
}

/// `node{ID}_{dof}_{quantity}_{unit}` in SI units.
pub fn column_name(node: u32, dof: u8, quantity: Quantity) -> String {
    let rotation = dof > 3;
    let suffix = match (quantity, rotation) {
        (Quantity::Displacement, false) => "disp_m",
        (Quantity::Velocity, false) => "vel_m_s",
        (Quantity::Acceleration, false) => "accel_m_s2",
        (Quantity::Displacement, true) => "disp_rad",
        (Quantity::Velocity, true) => "vel_rad_s",
        (Quantity::Acceleration, true) => "accel_rad_s2",
    };
    format!("node{node}_{}_{suffix}", dof_name(dof))
}

pub(super) fn gcd(a: usize, b: usize) -> usize {
    if b == 0 {
        a
    } else {
        gcd(b, a % b)
    }
}
