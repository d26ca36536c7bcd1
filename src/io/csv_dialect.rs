//! CSV dialects told apart by their header: gyrocomp's own (a time column in seconds,
//! [`TIME_COLUMN_NAMES`], rates in deg/s) and the EuRoC MAV / TUM-VI layout that robotics datasets
//! and many ROS tools write (`#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1],…`).
//!
//! A EuRoC header maps onto gyrocomp's names, so every command reads such a file as it is: the
//! time column is `#timestamp [ns]` (nanoseconds, converted to seconds), `gx_dps`, `gy_dps` and
//! `gz_dps` select `w_RS_S_x`, `w_RS_S_y` and `w_RS_S_z`, and the angular rates (rad/s) are
//! converted to deg/s. A EuRoC column may also be asked for by its own name (`w_RS_S_x`, with or
//! without the unit); its values are converted the same way.

/// Accepted names of the time column of gyrocomp's dialect, in order of preference
/// (docs/design.md "CSV conventions").
pub const TIME_COLUMN_NAMES: [&str; 3] = ["t_s", "t", "time"];
/// Degrees per radian.
const DEG_PER_RAD: f64 = 180.0 / std::f64::consts::PI;
/// First header field of the EuRoC / TUM-VI layout (its unit, when given, is `[ns]`).
const EUROC_TIME: &str = "#timestamp";
/// EuRoC names of the gyro axes x, y, z (before the unit).
const EUROC_GYRO: [&str; 3] = ["w_RS_S_x", "w_RS_S_y", "w_RS_S_z"];
/// gyrocomp's names of the gyro axes x, y, z.
const GYRO: [&str; 3] = ["gx_dps", "gy_dps", "gz_dps"];

/// Index in the header `names` of the first of `candidates` (in their order of preference) that
/// it has: how a column with several accepted names is found (the time column, the temperature).
pub fn first_named(names: &[String], candidates: &[&str]) -> Option<usize> {
    candidates.iter().find_map(|&wanted| names.iter().position(|n| n == wanted))
}

/// The layout of a header.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Dialect {
    /// gyrocomp's: time in seconds, rates in deg/s, names as in the file.
    Gyrocomp,
    /// EuRoC MAV / TUM-VI: time in ns, rates in rad/s (module documentation).
    Euroc,
}

/// Where a wanted column is and how its values become gyrocomp's units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Resolved {
    /// Index of the column in the header.
    pub index: usize,
    /// Factor to gyrocomp's unit (deg/s; seconds for time).
    pub scale: f64,
}

impl Dialect {
    /// The dialect of a header (its field names, trimmed).
    pub fn of(names: &[String]) -> Self {
        match names.first() {
            Some(first) if first.starts_with(EUROC_TIME) => Self::Euroc,
            _ => Self::Gyrocomp,
        }
    }

    /// The time column: its index, its name and the factor to seconds; `None` when absent.
    pub fn time(self, names: &[String]) -> Option<(Resolved, String)> {
        match self {
            Self::Gyrocomp => first_named(names, &TIME_COLUMN_NAMES)
                .map(|index| (Resolved { index, scale: 1.0 }, names[index].clone())),
            Self::Euroc => Some((Resolved { index: 0, scale: 1e-9 }, names[0].clone())),
        }
    }

    /// The wanted value column; `None` when the header lacks it.
    pub fn column(self, names: &[String], wanted: &str) -> Option<Resolved> {
        let exact = names.iter().position(|n| n == wanted);
        match self {
            Self::Gyrocomp => exact.map(|index| Resolved { index, scale: 1.0 }),
            Self::Euroc => {
                let euroc = GYRO.iter().position(|&g| g == wanted).map_or(wanted, |axis| EUROC_GYRO[axis]);
                let is_gyro = EUROC_GYRO.contains(&euroc);
                let index =
                    names.iter().position(|n| n == euroc || n.split_whitespace().next() == Some(euroc)).or(exact)?;
                Some(Resolved { index, scale: if is_gyro { DEG_PER_RAD } else { 1.0 } })
            }
        }
    }

    /// Help for a missing time column.
    pub fn time_names(self) -> String {
        match self {
            Self::Gyrocomp => TIME_COLUMN_NAMES.join("` or `"),
            Self::Euroc => EUROC_TIME.to_owned(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(text: &str) -> Vec<String> {
        text.split(',').map(|s| s.trim().to_owned()).collect()
    }

    #[test]
    fn a_euroc_header_maps_gyrocomp_names_and_units() {
        let h = names("#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1],w_RS_S_z [rad s^-1],a_RS_S_x [m s^-2]");
        let d = Dialect::of(&h);
        assert_eq!(d, Dialect::Euroc);
        assert_eq!(d.time(&h).unwrap(), (Resolved { index: 0, scale: 1e-9 }, "#timestamp [ns]".to_owned()));
        assert_eq!(d.column(&h, "gz_dps"), Some(Resolved { index: 3, scale: DEG_PER_RAD }));
        assert_eq!(d.column(&h, "w_RS_S_y"), Some(Resolved { index: 2, scale: DEG_PER_RAD }));
        assert_eq!(d.column(&h, "a_RS_S_x [m s^-2]"), Some(Resolved { index: 4, scale: 1.0 }));
        assert_eq!(d.column(&h, "temp_c"), None);
        let ours = names("t_s,gx_dps,temp_c");
        assert_eq!(Dialect::of(&ours), Dialect::Gyrocomp);
        assert_eq!(Dialect::Gyrocomp.column(&ours, "gx_dps"), Some(Resolved { index: 1, scale: 1.0 }));
        assert_eq!(Dialect::Gyrocomp.time(&ours).unwrap().0, Resolved { index: 0, scale: 1.0 });
    }
}
