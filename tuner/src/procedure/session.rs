//! The interpreter's state while a procedure runs: the case, the current model values, the
//! settings, the output folder, the grids of loop 3 and what the commands left so far.

use super::words::TargetValue;
use crate::calibrate::CalibrateSettings;
use crate::case::MeasuredCase;
use crate::damping::{DampingReport, Loop3, RunControl};
use crate::decay::DecayRecord;
use crate::error::{Result, TuneError};
use crate::fe::SpringState;
use crate::loops::LoopReport;
use crate::output::OutDir;
use std::path::{Path, PathBuf};

/// The interpreter's state.
pub(crate) struct Session {
    /// The procedure file (its folder anchors `case`, its name the default output folder).
    pub path: PathBuf,
    pub case: Option<MeasuredCase>,
    pub state: Option<SpringState>,
    pub settings: CalibrateSettings,
    pub out: Option<OutDir>,
    /// The output folder came from the command line: the file's `out` is ignored.
    pub out_fixed: bool,
    pub loop3: Option<Loop3>,
    pub loops: Vec<LoopReport>,
    pub damping: Option<DampingReport>,
    pub record: Option<DecayRecord>,
    pub control: RunControl,
}

impl Session {
    /// A fresh session for the procedure at `path`; `out` is the command line's folder.
    pub fn new(path: &Path, out: Option<OutDir>, control: &RunControl) -> Self {
        Session {
            path: path.to_path_buf(),
            case: None,
            state: None,
            settings: CalibrateSettings::default(),
            out_fixed: out.is_some(),
            out,
            loop3: None,
            loops: Vec::new(),
            damping: None,
            record: None,
            control: control.clone(),
        }
    }

    /// The output folder, created as `out/<procedure name>` at the first write when
    /// neither the command line nor an `out` line named one.
    pub fn out(&mut self) -> Result<OutDir> {
        if let Some(out) = &self.out {
            return Ok(out.clone());
        }
        let stem = self
            .path
            .file_stem()
            .map_or("procedure".into(), |s| s.to_string_lossy().into_owned());
        let out = OutDir::create(Path::new("out").join(stem))?;
        self.out = Some(out.clone());
        Ok(out)
    }

    /// The case read by `case`.
    pub fn case(&self) -> Result<&MeasuredCase> {
        self.case.as_ref().ok_or_else(|| {
            TuneError::Invalid("no case yet; put `case PATH` before this line".into())
        })
    }

    /// The current model values.
    pub fn state(&mut self) -> Result<&mut SpringState> {
        self.state.as_mut().ok_or_else(|| {
            TuneError::Invalid("no case yet; put `case PATH` before this line".into())
        })
    }

    /// A number, or the case's target `field`.
    pub fn target(&self, value: TargetValue, field: &'static str) -> Result<f64> {
        match value {
            TargetValue::Number(x) => Ok(x),
            TargetValue::Target => Ok(self.case()?.target(field)?),
        }
    }

    /// The model changed: grids run so far were for another model.
    pub fn model_changed(&mut self) {
        self.loop3 = None;
    }
}
