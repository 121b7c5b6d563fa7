//! The time series (`series.csv`): one row per sampled step with the
//! energies (and, when a wall moves, the work the walls did), the
//! contact counts, the force on each wall and (after all
//! the forces) the torque on each wall about its torque point; and the
//! collision log (`collisions.csv`), one row per completed contact. SI,
//! units in the column names.

use crate::dynamics::collisions::{Collision, Partner};
use crate::simulation::collision_columns::VALUES;
use crate::simulation::Observation;
use std::io::Write;

/// One cell of a series row: a count, or an SI value (the unit is in
/// the column's name).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Cell {
    Count(u64),
    Value(f64),
}

/// The column names of a series row for a scene of `walls` walls, units
/// in the names: the energies (with `work`: moving walls, their work
/// after the dissipated energy; a scene of fixed walls keeps its
/// columns), the contact counts, then the force on each wall and (after
/// all the forces) the torque on each wall.
pub fn series_header(walls: usize, work: bool) -> Vec<String> {
    let mut header: Vec<String> = [
        "step",
        "time_s",
        "kinetic_energy_J",
        "elastic_energy_J",
        "potential_energy_J",
        "dissipated_energy_J",
        "particle_contacts",
        "wall_contacts",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    if work {
        header.insert(6, "work_by_walls_J".to_string());
    }
    for k in 0..walls {
        for axis in ["x", "y", "z"] {
            header.push(format!("wall{k}_force_{axis}_N"));
        }
    }
    for k in 0..walls {
        for axis in ["x", "y", "z"] {
            header.push(format!("wall{k}_torque_{axis}_N_m"));
        }
    }
    header
}

/// The columns of a moving or force-controlled wall `k` (issue 27,
/// after the torques, walls in file order): its reference point's
/// displacement, the angle it turned, its velocity and angular velocity
/// (`pipeline::wall_states`).
pub fn motion_columns(k: usize) -> Vec<String> {
    let mut out = Vec::with_capacity(10);
    for axis in ["x", "y", "z"] {
        out.push(format!("wall{k}_position_{axis}_m"));
    }
    out.push(format!("wall{k}_angle_rad"));
    for axis in ["x", "y", "z"] {
        out.push(format!("wall{k}_velocity_{axis}_m_s"));
    }
    for axis in ["x", "y", "z"] {
        out.push(format!("wall{k}_angular_velocity_{axis}_rad_s"));
    }
    out
}

/// The columns of a moving `[[particles]]` group `k` (issue 27, after the
/// moving walls'): its motion as [`motion_columns`], then the force and
/// the torque (about the motion's centre now) the spheres put on it
/// (`pipeline::moving_groups`).
pub fn group_columns(k: usize) -> Vec<String> {
    let mut out: Vec<String> = motion_columns(k)
        .into_iter()
        .map(|c| c.replacen("wall", "particles", 1))
        .collect();
    for (what, unit) in [("force", "N"), ("torque", "N_m")] {
        for axis in ["x", "y", "z"] {
            out.push(format!("particles{k}_{what}_{axis}_{unit}"));
        }
    }
    out
}

/// The columns a scene that removes spheres (`crate::removal`) adds after
/// the torques: the spheres removed so far, their mass, the energy they
/// carried out.
pub const REMOVED_COLUMNS: [&str; 3] = [
    "deleted_particles",
    "deleted_mass_kg",
    "carried_out_energy_J",
];

/// The column a scene with walls that appear or vanish (`walls::gate`)
/// adds after the removal's: the gate energy G booked so far.
pub const GATE_COLUMN: &str = "gate_energy_J";

/// The columns `output.wall_force_mean` adds after all the others: each
/// wall's force averaged over every step since the previous row
/// ([`Observation::wall_force_means`]), file order.
pub fn mean_force_columns(walls: usize) -> Vec<String> {
    (0..walls)
        .flat_map(|k| ["x", "y", "z"].map(|axis| format!("wall{k}_mean_force_{axis}_N")))
        .collect()
}

/// Every column of the series row of `o`, `previous` the row before it
/// (`None`: the first row, after t = 0 with nothing removed): (names with
/// units, cells), in series.csv's order: [`series_header`]'s energies,
/// work, counts, wall forces and torques; the removal's columns when
/// `o.removed` is given; the gate energy when `o.gate_energy` is; each
/// moving wall's [`motion_columns`] and each moving group's
/// [`group_columns`]; each outlet's `crate::outlets::outlet_columns`
/// (its rate since `previous`); each inlet's `crate::inlets::inlet_columns`
/// and, with inlets, the energy brought in; last, with
/// `o.wall_force_means`, the [`mean_force_columns`]. The one builder of the
/// columns: series.csv ([`write_series`]) and Python's `Scene.observe()`.
pub fn series_columns(o: &Observation, previous: Option<&Observation>) -> (Vec<String>, Vec<Cell>) {
    let mut header = series_header(o.wall_forces.len(), o.work_by_walls.is_some());
    let mut cells = vec![
        Cell::Count(o.step),
        Cell::Value(o.time),
        Cell::Value(o.kinetic_energy),
        Cell::Value(o.elastic_energy),
        Cell::Value(o.potential_energy),
        Cell::Value(o.dissipated_energy),
        Cell::Count(o.particle_contacts as u64),
        Cell::Count(o.wall_contacts as u64),
    ];
    if let Some(w) = o.work_by_walls {
        cells.insert(6, Cell::Value(w));
    }
    for f in o.wall_forces.iter().chain(&o.wall_torques) {
        cells.extend(f.iter().map(|&x| Cell::Value(x)));
    }
    if let Some(r) = o.removed {
        header.extend(REMOVED_COLUMNS.iter().map(|s| s.to_string()));
        cells.extend([
            Cell::Count(r.particles),
            Cell::Value(r.mass),
            Cell::Value(r.energy),
        ]);
    }
    if let Some(g) = o.gate_energy {
        header.push(GATE_COLUMN.to_string());
        cells.push(Cell::Value(g));
    }
    for m in &o.wall_motions {
        header.extend(motion_columns(m.wall));
        cells.extend(m.position.iter().map(|&x| Cell::Value(x)));
        cells.push(Cell::Value(m.angle));
        for v in [m.velocity, m.angular_velocity] {
            cells.extend(v.iter().map(|&x| Cell::Value(x)));
        }
    }
    for g in &o.group_motions {
        header.extend(group_columns(g.group));
        cells.extend(g.position.iter().map(|&x| Cell::Value(x)));
        cells.push(Cell::Value(g.angle));
        for v in [g.velocity, g.angular_velocity, g.force, g.torque] {
            cells.extend(v.iter().map(|&x| Cell::Value(x)));
        }
    }
    // The outlets' columns (`crate::outlets`), only when there are any.
    for (k, r) in o.outlets.iter().enumerate() {
        header.extend(crate::outlets::outlet_columns(k));
        cells.extend([
            Cell::Count(r.count),
            Cell::Value(r.mass),
            Cell::Value(crate::outlets::rate_since(o, previous, k)),
        ]);
    }
    // The inlets' columns (`crate::inlets`), only when there are any.
    for (k, r) in o.inlets.iter().enumerate() {
        header.extend(crate::inlets::inlet_columns(k));
        cells.extend([Cell::Count(r.count), Cell::Value(r.mass)]);
    }
    if !o.inlets.is_empty() {
        header.push(crate::inlets::BROUGHT_IN_COLUMN.to_string());
        cells.push(Cell::Value(o.inlets.iter().map(|r| r.energy).sum()));
    }
    // The walls' forces averaged since the previous row, when asked: after
    // every other column, so that those keep their places.
    if let Some(means) = &o.wall_force_means {
        header.extend(mean_force_columns(means.len()));
        cells.extend(means.iter().flatten().map(|&x| Cell::Value(x)));
    }
    (header, cells)
}

/// Writes `rows` (in time order) for a scene of `walls` walls: the
/// [`series_columns`] of each row after the previous one (no rows: the
/// header of `walls` walls alone).
pub fn write_series(w: &mut dyn Write, rows: &[Observation], walls: usize) -> csv::Result<()> {
    let mut out = csv::Writer::from_writer(w);
    let header = match rows.first() {
        Some(o) => series_columns(o, None).0,
        None => series_header(walls, false),
    };
    out.write_record(header)?;
    for (i, o) in rows.iter().enumerate() {
        let previous = i.checked_sub(1).map(|p| &rows[p]);
        let record = series_columns(o, previous).1.into_iter().map(|c| match c {
            Cell::Count(n) => n.to_string(),
            Cell::Value(x) => format!("{x:e}"),
        });
        out.write_record(record)?;
    }
    out.flush()?;
    Ok(())
}

/// The partner of a collision as the outputs name it: a sphere's input
/// index, or `wall:K` for wall K (file order: a plane, or one of the
/// boundary particles of a boundary-particle wall, whose input index is
/// [`boundary_particle`]).
pub fn partner_name(j: &Partner) -> String {
    match j {
        Partner::Body(b) => b.to_string(),
        Partner::Wall(k) | Partner::BoundaryParticle { wall: k, .. } => format!("wall:{k}"),
    }
}

/// The input index of the boundary particle hit, if the partner is one.
pub fn boundary_particle(j: &Partner) -> Option<usize> {
    match j {
        Partner::BoundaryParticle { body, .. } => Some(*body),
        _ => None,
    }
}

/// Writes the collision log; with `triangle_column` (a scene with a
/// triangle-mesh wall) a `triangle` column after `boundary_particle`: the
/// mesh triangle a wall contact was on ([`Collision::triangle`]), empty for
/// other partners. Without it the file is as it was before mesh walls.
pub fn write_collisions(
    w: &mut dyn Write,
    log: &[Collision],
    triangle_column: bool,
) -> csv::Result<()> {
    let mut out = csv::Writer::from_writer(w);
    let mut header = vec!["i", "j", "boundary_particle"];
    if triangle_column {
        header.push("triangle");
    }
    // The number columns: `VALUES`' fields in their order, with units.
    header.extend([
        "t_start_s",
        "t_end_s",
        "duration_s",
        "max_overlap_m",
        "max_normal_force_N",
        "impact_normal_velocity_m_s",
        "rebound_normal_velocity_m_s",
        "impact_tangential_velocity_m_s",
        "rebound_tangential_velocity_m_s",
        "impact_spin_i_x_rad_s",
        "impact_spin_i_y_rad_s",
        "impact_spin_i_z_rad_s",
        "rebound_spin_i_x_rad_s",
        "rebound_spin_i_y_rad_s",
        "rebound_spin_i_z_rad_s",
        "impact_spin_j_x_rad_s",
        "impact_spin_j_y_rad_s",
        "impact_spin_j_z_rad_s",
        "rebound_spin_j_x_rad_s",
        "rebound_spin_j_y_rad_s",
        "rebound_spin_j_z_rad_s",
    ]);
    out.write_record(&header)?;
    // Each field written as it is formatted: no String a cell (the
    // formatting is most of this writer's work: `ExpFormat`).
    let mut number = super::exp_format::ExpFormat::default();
    for c in log {
        out.write_field(c.i.to_string())?;
        out.write_field(partner_name(&c.j))?;
        out.write_field(boundary_particle(&c.j).map_or(String::new(), |b| b.to_string()))?;
        if triangle_column {
            out.write_field(c.triangle.map_or(String::new(), |t| t.to_string()))?;
        }
        for value in &VALUES {
            out.write_field(number.format(value.of(c)))?;
        }
        out.write_record(None::<&[u8]>)?;
    }
    out.flush()?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A moving group's columns: its motion as a wall's, renamed, then
    /// its force and torque.
    #[test]
    fn group_columns_follow_the_motion_columns() {
        let c = group_columns(2);
        assert_eq!(c.len(), 16);
        assert_eq!(c[0], "particles2_position_x_m");
        assert_eq!(c[3], "particles2_angle_rad");
        assert_eq!(c[9], "particles2_angular_velocity_z_rad_s");
        assert_eq!(c[10], "particles2_force_x_N");
        assert_eq!(c[15], "particles2_torque_z_N_m");
    }

    #[test]
    fn header_has_force_then_torque_triples_per_wall_and_rows_follow() {
        let o = Observation {
            step: 10,
            time: 2e-5,
            kinetic_energy: 1.5,
            elastic_energy: 0.0,
            potential_energy: -1.0,
            dissipated_energy: 0.0,
            particle_contacts: 3,
            wall_contacts: 1,
            wall_forces: vec![[0.0, 0.0, 9.81], [1.0, 0.0, 0.0]],
            wall_torques: vec![[0.5, 0.0, 0.0], [0.0, -2.0, 0.0]],
            work_by_walls: None,
            removed: None,
            wall_motions: Vec::new(),
            group_motions: Vec::new(),
            outlets: Vec::new(),
            gate_energy: None,
            inlets: Vec::new(),
            dissipated_by_contacts: None,
            wall_force_means: None,
        };
        let mut out = Vec::new();
        write_series(&mut out, std::slice::from_ref(&o), 2).unwrap();
        let text = String::from_utf8(out).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert!(lines[0].ends_with("wall0_force_x_N,wall0_force_y_N,wall0_force_z_N,wall1_force_x_N,wall1_force_y_N,wall1_force_z_N,wall0_torque_x_N_m,wall0_torque_y_N_m,wall0_torque_z_N_m,wall1_torque_x_N_m,wall1_torque_y_N_m,wall1_torque_z_N_m"));
        assert_eq!(
            lines[1],
            "10,2e-5,1.5e0,0e0,-1e0,0e0,3,1,0e0,0e0,9.81e0,1e0,0e0,0e0,5e-1,0e0,0e0,0e0,-2e0,0e0"
        );
        // A moving wall adds its work after the dissipated energy.
        let moving = Observation {
            work_by_walls: Some(0.25),
            removed: None,
            ..o
        };
        let mut out = Vec::new();
        write_series(&mut out, std::slice::from_ref(&moving), 2).unwrap();
        let text = String::from_utf8(out).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert!(lines[0].starts_with(
            "step,time_s,kinetic_energy_J,elastic_energy_J,potential_energy_J,\
             dissipated_energy_J,work_by_walls_J,particle_contacts,"
        ));
        assert!(lines[1].starts_with("10,2e-5,1.5e0,0e0,-1e0,0e0,2.5e-1,3,1,"));
        // A moving wall's motion after the torques: position, angle,
        // velocity, angular velocity.
        let moving = Observation {
            wall_motions: vec![crate::pipeline::wall_states::WallMotionState {
                wall: 1,
                position: [0.0, 0.0, -2e-3],
                angle: 0.5,
                velocity: [0.0, 0.0, -1e-3],
                angular_velocity: [0.0, 0.0, 0.25],
            }],
            ..moving
        };
        let mut out = Vec::new();
        write_series(&mut out, std::slice::from_ref(&moving), 2).unwrap();
        let text = String::from_utf8(out).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert!(lines[0].ends_with(
            "wall1_torque_z_N_m,wall1_position_x_m,wall1_position_y_m,wall1_position_z_m,\
             wall1_angle_rad,wall1_velocity_x_m_s,wall1_velocity_y_m_s,wall1_velocity_z_m_s,\
             wall1_angular_velocity_x_rad_s,wall1_angular_velocity_y_rad_s,\
             wall1_angular_velocity_z_rad_s"
        ));
        assert!(lines[1].ends_with(",0e0,0e0,-2e-3,5e-1,0e0,0e0,-1e-3,0e0,0e0,2.5e-1"));
        assert_eq!(
            series_columns(&moving, None).0,
            lines[0].split(',').collect::<Vec<_>>()
        );
        assert_eq!(partner_name(&Partner::Wall(2)), "wall:2");
        assert_eq!(partner_name(&Partner::Body(5)), "5");
    }

    /// Each number column of collisions.csv holds the field its header
    /// names: a row whose fields are all different, the header's names
    /// matched to the fields by hand (not through `VALUES`), each value
    /// read back from the text. Exact: `ExpFormat` writes the shortest
    /// digits that read back to the same double.
    #[test]
    fn each_collision_column_holds_the_field_it_names() {
        let x = |k: u32| 1.0 + f64::from(k) / 64.0;
        let c = Collision {
            i: 3,
            j: Partner::BoundaryParticle { wall: 1, body: 7 },
            t_start: x(0),
            t_end: x(1),
            duration: x(2),
            max_overlap: x(3),
            max_normal_force: x(4),
            impact_normal_velocity: x(5),
            rebound_normal_velocity: x(6),
            impact_tangential_velocity: x(7),
            rebound_tangential_velocity: x(8),
            impact_spin_i: [x(9), x(10), x(11)],
            rebound_spin_i: [x(12), x(13), x(14)],
            impact_spin_j: [x(15), x(16), x(17)],
            rebound_spin_j: [x(18), x(19), x(20)],
            triangle: None,
        };
        let mut expected: Vec<(String, f64)> = [
            ("t_start_s", c.t_start),
            ("t_end_s", c.t_end),
            ("duration_s", c.duration),
            ("max_overlap_m", c.max_overlap),
            ("max_normal_force_N", c.max_normal_force),
            ("impact_normal_velocity_m_s", c.impact_normal_velocity),
            ("rebound_normal_velocity_m_s", c.rebound_normal_velocity),
            (
                "impact_tangential_velocity_m_s",
                c.impact_tangential_velocity,
            ),
            (
                "rebound_tangential_velocity_m_s",
                c.rebound_tangential_velocity,
            ),
        ]
        .map(|(name, value)| (name.to_string(), value))
        .to_vec();
        for (name, spin) in [
            ("impact_spin_i", c.impact_spin_i),
            ("rebound_spin_i", c.rebound_spin_i),
            ("impact_spin_j", c.impact_spin_j),
            ("rebound_spin_j", c.rebound_spin_j),
        ] {
            for (axis, value) in ["x", "y", "z"].iter().zip(spin) {
                expected.push((format!("{name}_{axis}_rad_s"), value));
            }
        }
        let mut csv = Vec::new();
        write_collisions(&mut csv, &[c], false).unwrap();
        let text = String::from_utf8(csv).unwrap();
        let mut lines = text.lines();
        let header: Vec<&str> = lines.next().unwrap().split(',').collect();
        let row: Vec<&str> = lines.next().unwrap().split(',').collect();
        assert_eq!(&header[..3], &["i", "j", "boundary_particle"]);
        assert_eq!(&row[..3], &["3", "wall:1", "7"]);
        assert_eq!(header.len(), 3 + expected.len());
        for (name, value) in expected {
            let k = header.iter().position(|h| *h == name.as_str()).unwrap();
            assert_eq!(row[k].parse::<f64>().unwrap(), value, "{name}");
        }
    }
}
