//! The simulator's CSV (`gyrocomp sim`, `replay`'s default recording):
//! `t_s,gx_dps,gy_dps,gz_dps,temp_c,gx_drift_dps,gy_drift_dps,gz_drift_dps`, the drift columns
//! being the truth (every error term except white noise and quantisation).

use std::io;
use std::path::Path;

use super::CsvColumnsWriter;
use crate::sim::{AXIS_NAMES, SimOutput};

/// Writes `out` to `path` (`-` for standard output) in the simulator's columns; the error names
/// the file.
pub fn write_sim_csv(path: &Path, out: &SimOutput) -> io::Result<()> {
    let mut header: Vec<String> = vec!["t_s".into()];
    header.extend(AXIS_NAMES.iter().map(|a| format!("g{a}_dps")));
    header.push("temp_c".into());
    header.extend(AXIS_NAMES.iter().map(|a| format!("g{a}_drift_dps")));
    let header: Vec<&str> = header.iter().map(String::as_str).collect();
    let [x, y, z] = &out.axes;
    let columns: [&[f64]; 8] = [&out.t_s, &x.raw, &y.raw, &z.raw, &out.temp_c, &x.drift, &y.drift, &z.drift];
    CsvColumnsWriter::create(path)
        .and_then(|w| w.write(&header, &columns))
        .map_err(|e| io::Error::new(e.kind(), format!("{}: cannot write: {e}", path.display())))
}
