//! The straight line of beam nodes a moving contact runs on (`MOVING CONTACT`): which
//! global axis it follows, and the order of its nodes along it. Used by the model's
//! check (the error names the card's line) and by the analysis that moves the point.
//!
//! # What a contact line is
//! The contact point's deflection is the cubic Hermite interpolation of one beam
//! element's end translations and rotations, so the line must be one wire:
//! - its nodes lie on one straight line parallel to a global axis: with `spread_i` the
//!   largest `|x_i - x_i(first node)|`, the axis is the coordinate of largest spread and
//!   the other two spreads are at most [`STRAIGHT`] times it;
//! - the axis is not the contact's own DOF (a head pressing along the wire has no
//!   penetration to measure);
//! - no two nodes share a point, and every two nodes next to each other along the axis
//!   are the two ends of one element of the model (the interpolation on a segment reads
//!   that element's end rotations). Two wires named in one list fail the straightness
//!   test when they are apart across the axis; nodes of one straight line that are not
//!   joined one to the next fail the last test.

/// Off-axis spread over the spread along the axis under which nodes count as
/// collinear: far above the rounding of printed coordinates (1e-15 relative for
/// Mentat's 16 digits), far below any deliberate offset (a contact wire's 1 mm
/// stagger on a 50 m span is 2e-5).
pub const STRAIGHT: f64 = 1e-9;

/// A contact line resolved: its axis, the third axis (neither the axis nor the DOF's)
/// and the line's nodes in axis order (indices into the caller's list).
#[derive(Debug, Clone, PartialEq)]
pub struct ContactAxis {
    /// The global axis the line follows (0 = x, 1 = y, 2 = z).
    pub axis: usize,
    /// The axis neither along the line nor along the contact's DOF.
    pub third: usize,
    /// The caller's nodes in increasing coordinate along the axis.
    pub order: Vec<usize>,
}

/// Why a list of nodes is not a contact line: `(what is wrong, what was expected)`.
pub type LineProblem = (String, String);

/// Resolves the line of `nodes` (`(id, xyz)` each, at least two) for a contact along
/// `dof` (1..=3); `joined(a, b)` says whether an element joins nodes `a` and `b`.
pub fn contact_axis(
    nodes: &[(u32, [f64; 3])],
    dof: u8,
    joined: impl Fn(u32, u32) -> bool,
) -> Result<ContactAxis, LineProblem> {
    let d = usize::from(dof.clamp(1, 3) - 1);
    let Some(&(_, first)) = nodes.first() else {
        return Err(("a line without nodes".into(), "two nodes or more".into()));
    };
    let mut spread = [0.0_f64; 3];
    for (_, p) in nodes {
        for (s, (a, b)) in spread.iter_mut().zip(p.iter().zip(&first)) {
            *s = s.max((a - b).abs());
        }
    }
    let axis = (0..3)
        .max_by(|&a, &b| spread[a].total_cmp(&spread[b]))
        .unwrap_or(0);
    let along = "nodes on one straight line parallel to a global axis other than the \
                 contact's DOF (one wire)";
    if spread[axis] == 0.0 {
        return Err((
            format!("the line's {} nodes all lie at one point", nodes.len()),
            along.into(),
        ));
    }
    if axis == d {
        return Err((
            format!(
                "the line runs along DOF {dof}, the contact's own direction (spread x, y, \
                 z: {spread:?} mm)"
            ),
            format!("a contact DOF across the line (the line along DOF {dof}: press along another translation)"),
        ));
    }
    let off: Vec<usize> = (0..3).filter(|&i| i != axis).collect();
    if off.iter().any(|&i| spread[i] > STRAIGHT * spread[axis]) {
        return Err((
            format!(
                "the line's nodes are not on one straight line (spread x, y, z: \
                 {spread:?} mm; two wires in one list?)"
            ),
            along.into(),
        ));
    }
    let mut order: Vec<usize> = (0..nodes.len()).collect();
    order.sort_by(|&a, &b| nodes[a].1[axis].total_cmp(&nodes[b].1[axis]));
    let tolerance = STRAIGHT * spread[axis];
    for w in order.windows(2) {
        let ((a, pa), (b, pb)) = (nodes[w[0]], nodes[w[1]]);
        if pb[axis] - pa[axis] <= tolerance {
            return Err((
                format!("nodes {a} and {b} of the line lie at one point"),
                "distinct nodes along the line".into(),
            ));
        }
        if !joined(a, b) {
            return Err((
                format!("no element joins nodes {a} and {b}, next to each other on the line"),
                "the nodes of one wire, each joined to the next by a beam element".into(),
            ));
        }
    }
    Ok(ContactAxis {
        axis,
        third: 3 - axis - d,
        order,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line(points: &[[f64; 3]]) -> Vec<(u32, [f64; 3])> {
        points
            .iter()
            .enumerate()
            .map(|(i, p)| (i as u32 + 1, *p))
            .collect()
    }

    fn chain(a: u32, b: u32) -> bool {
        a.abs_diff(b) == 1
    }

    #[test]
    fn a_wire_along_x_pressed_along_z_is_a_line() {
        // Listed out of order: 3 at x = 2000 first.
        let nodes = [
            (3, [2000.0, 0.0, 0.0]),
            (1, [0.0, 0.0, 0.0]),
            (2, [1000.0, 0.0, 0.0]),
        ];
        let c = contact_axis(&nodes, 3, chain).unwrap();
        assert_eq!((c.axis, c.third), (0, 1));
        assert_eq!(c.order, [1, 2, 0]);
    }

    #[test]
    fn what_is_not_a_line_is_named() {
        let wire = [[0.0, 0.0, 0.0], [1000.0, 0.0, 0.0], [2000.0, 0.0, 0.0]];
        // Pressed along the wire's own axis.
        let e = contact_axis(&line(&wire), 1, chain).unwrap_err();
        assert!(e.0.contains("own direction"), "{e:?}");
        // Two wires, 1.2 m apart along the contact's DOF.
        let mut both = wire.to_vec();
        both.extend(wire.iter().map(|p| [p[0], 0.0, 1200.0]));
        let e = contact_axis(&line(&both), 3, |_, _| true).unwrap_err();
        assert!(e.0.contains("not on one straight line"), "{e:?}");
        // ... or across it.
        let mut both = wire.to_vec();
        both.extend(wire.iter().map(|p| [p[0], 300.0, 0.0]));
        assert!(contact_axis(&line(&both), 3, |_, _| true).is_err());
        // Straight but not joined one to the next (every other node of a wire).
        let e = contact_axis(&line(&wire), 3, |_, _| false).unwrap_err();
        assert!(e.0.contains("no element joins nodes 1 and 2"), "{e:?}");
        // Two nodes at one point.
        let e = contact_axis(&line(&[wire[0], wire[1], wire[1]]), 3, |_, _| true).unwrap_err();
        assert!(e.0.contains("lie at one point"), "{e:?}");
        let e = contact_axis(&line(&[wire[0], wire[0]]), 3, |_, _| true).unwrap_err();
        assert!(e.0.contains("all lie at one point"), "{e:?}");
        // A tilt of 1e-6 is refused, one of 1e-12 (printing) accepted.
        let tilt = |t: f64| line(&[[0.0, 0.0, 0.0], [1000.0, 0.0, 1000.0 * t]]);
        assert!(contact_axis(&tilt(1e-6), 3, chain).is_err());
        assert!(contact_axis(&tilt(1e-12), 3, chain).is_ok());
    }
}
