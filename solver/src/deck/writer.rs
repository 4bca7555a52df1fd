//! Model -> deck text, in the same Marc style the reader reads: one card per block,
//! a comment with the units above each kind of data line, lists compressed to
//! `a TO b` ranges (or a set's name when a set holds exactly the list), long lists
//! continued with `C`. Reals are printed in Rust's shortest round-trip form (`{:?}`:
//! `7.85e-9`, `190708.0`), so read(write(m)) == m bit for bit.
//!
//! What cannot round-trip: titles are single lines (line breaks are written as
//! blanks; blanks at either end are lost) and names must be names in the deck's
//! sense (a letter or `_` first); a point load keeps only its non-zero components, in
//! DOF order. A model the reader produced always round-trips.

use std::fmt::Write;

use crate::model::{
    Analysis, Integrator, MatrixElement, Model, PointElement, PointLoad, Quantity, Section,
    TransientMethod,
};

/// The `DMIG` card of `elements` (empty text for none), as [`write`] writes it: a name
/// that is a number is the group's id, any other name follows an id counted from 1.
pub fn dmig_card(elements: &[MatrixElement]) -> String {
    let mut out = String::new();
    if elements.is_empty() {
        return out;
    }
    out.push_str("DMIG\n");
    for (i, e) in elements.iter().enumerate() {
        let n = e.size();
        let flag = u8::from(!e.damping.is_empty());
        out.push_str("$ id, n, 1 if a damping matrix follows, name\n");
        match e.name.parse::<u32>() {
            Ok(id) if id > 0 => out.push_str(&format!("{id}, {n}, {flag}\n")),
            _ => out.push_str(&format!("{}, {n}, {flag}, {}\n", i + 1, e.name)),
        }
        out.push_str("$ node, dof of each row\n");
        for &(node, dof) in &e.dofs {
            out.push_str(&format!("{node}, {dof}\n"));
        }
        let damping = (flag == 1).then_some(("damping (N s/mm)", &e.damping));
        for (what, a) in [("stiffness (N/mm)", &e.stiffness), ("mass (t)", &e.mass)]
            .into_iter()
            .chain(damping)
        {
            out.push_str(&format!("$ {what}, row by row\n"));
            for row in a.chunks(n.max(1)) {
                out.push_str(&nums(row.iter().copied()));
                out.push('\n');
            }
        }
    }
    out
}

/// The value a nonlinear point card writes for an element, if it writes one.
type PointValue = fn(&PointElement) -> Option<f64>;

/// Ids per list line before a `C` continuation.
const ITEMS_PER_LINE: usize = 10;

/// Writes a model as a deck that reads back to an equal model.
pub fn write(model: &Model) -> String {
    let mut w = Writer {
        out: String::new(),
        model,
    };
    w.parameters();
    w.model_definition();
    w.history();
    w.out
}

struct Writer<'m> {
    out: String,
    model: &'m Model,
}

fn num(x: f64) -> String {
    format!("{x:?}")
}

fn nums(xs: impl IntoIterator<Item = f64>) -> String {
    xs.into_iter().map(num).collect::<Vec<_>>().join(", ")
}

fn node_sets(m: &Model) -> Vec<(&str, &[u32])> {
    m.node_sets
        .iter()
        .map(|s| (s.name.as_str(), s.nodes.as_slice()))
        .collect()
}

fn element_sets(m: &Model) -> Vec<(&str, &[u32])> {
    m.element_sets
        .iter()
        .map(|s| (s.name.as_str(), s.elements.as_slice()))
        .collect()
}

fn one_line(text: &str) -> String {
    text.replace(['\r', '\n'], " ")
}

impl Writer<'_> {
    fn line(&mut self, text: &str) {
        self.out.push_str(text);
        self.out.push('\n');
    }

    fn comment(&mut self, text: &str) {
        let _ = writeln!(self.out, "$ {text}");
    }

    fn rule(&mut self, what: &str) {
        let _ = writeln!(self.out, "$ {:-<60} {what}", "");
    }

    /// A list of ids: a set's name if one holds exactly these ids, else ranges.
    fn list(&mut self, ids: &[u32], sets: &[(&str, &[u32])]) {
        if !ids.is_empty() {
            if let Some((name, _)) = sets.iter().find(|(_, s)| *s == ids) {
                self.line(name);
                return;
            }
        }
        self.ranges(ids);
    }

    /// Ids as `a TO b` runs and single ids, continued with `C` every few items. An
    /// empty list is a blank line.
    fn ranges(&mut self, ids: &[u32]) {
        let mut items = Vec::new();
        let mut i = 0;
        while i < ids.len() {
            let mut j = i;
            while j + 1 < ids.len() && u64::from(ids[j + 1]) == u64::from(ids[j]) + 1 {
                j += 1;
            }
            if j - i >= 2 {
                items.push(format!("{} TO {}", ids[i], ids[j]));
            } else {
                items.extend(ids[i..=j].iter().map(u32::to_string));
            }
            i = j + 1;
        }
        if items.is_empty() {
            self.line("");
            return;
        }
        let chunks: Vec<&[String]> = items.chunks(ITEMS_PER_LINE).collect();
        for (k, chunk) in chunks.iter().enumerate() {
            let mut text = chunk.join(", ");
            if k + 1 < chunks.len() {
                text.push_str(", C");
            }
            self.line(&text);
        }
    }

    fn parameters(&mut self) {
        let m = self.model;
        self.comment("coil input deck in MSC Marc's free format (reference: docs/deck.md)");
        self.comment(
            "units: length mm, force N, mass t (tonne), time s; E in MPa, density in t/mm^3,",
        );
        self.comment(
            "rotary inertia in t mm^2. DOFs: 1-3 = ux, uy, uz (mm); 4-6 = rx, ry, rz (rad)",
        );
        self.rule("parameters");
        if !m.title.is_empty() {
            self.line(&format!("TITLE, {}", one_line(&m.title)));
        }
        self.line(&format!(
            "SIZING, 0, {}, {}, 0",
            m.elements.len(),
            m.nodes.len()
        ));
        if !m.element_types.is_empty() {
            let types: Vec<String> = m
                .element_types
                .iter()
                .map(|t| t.number().to_string())
                .collect();
            self.line(&format!("ELEMENTS, {}", types.join(", ")));
        }
        if m.lumped_mass {
            self.comment("lumped mass for every element");
            self.line("LUMP");
        }
        self.line("END");
    }

    /// The model definition: the mesh, sets and tables, then the other cards in the
    /// order the reader expects (one method per family of cards).
    fn model_definition(&mut self) {
        let m = self.model;
        self.rule("model definition");

        self.line("CONNECTIVITY");
        self.comment("number of element lines");
        self.line(&m.elements.len().to_string());
        self.comment("element, type, node 1, node 2");
        for e in &m.elements {
            self.line(&format!(
                "{}, {}, {}, {}",
                e.id,
                e.kind.number(),
                e.nodes[0],
                e.nodes[1]
            ));
        }

        self.line("COORDINATES");
        self.comment("3 coordinates per node, number of node lines");
        self.line(&format!("3, {}, 0, 1", m.nodes.len()));
        self.comment("node, x, y, z (mm)");
        for n in &m.nodes {
            self.line(&format!("{}, {}", n.id, nums(n.xyz)));
        }

        for s in &m.node_sets {
            self.line(&format!("DEFINE, NODE, SET, {}", s.name));
            self.ranges(&s.nodes);
        }
        for s in &m.element_sets {
            self.line(&format!("DEFINE, ELEMENT, SET, {}", s.name));
            self.ranges(&s.elements);
        }

        for t in &m.tables {
            self.line(&format!("TABLE, {}", t.name));
            self.comment("time (s), factor");
            for &(time, factor) in &t.points {
                self.line(&nums([time, factor]));
            }
        }

        self.properties();
        self.attachments();
        self.loads_and_outputs();
    }

    /// Materials, geometries, Rayleigh damping, beam tensions, links and contacts.
    fn properties(&mut self) {
        let m = self.model;
        let node_sets = node_sets(m);
        let element_sets = element_sets(m);
        if !m.materials.is_empty() {
            self.line("ISOTROPIC");
            self.comment("number of materials");
            self.line(&m.materials.len().to_string());
            for (k, mat) in m.materials.iter().enumerate() {
                self.comment("id, name");
                self.line(&format!("{}, {}", k + 1, mat.name));
                self.comment("E (MPa), Poisson's ratio, density (t/mm^3)");
                self.line(&nums([mat.youngs_modulus, mat.poisson, mat.density]));
                self.comment("elements");
                self.list(&mat.elements, &element_sets);
            }
        }

        if !m.geometries.is_empty() {
            self.line("GEOMETRY");
            self.comment("number of geometries");
            self.line(&m.geometries.len().to_string());
            for (k, g) in m.geometries.iter().enumerate() {
                if !g.name.is_empty() {
                    self.comment("id, name");
                    self.line(&format!("{}, {}", k + 1, g.name));
                }
                match g.section {
                    Section::SolidCircle { diameter } => {
                        self.comment("solid circular wire: diameter (mm)");
                        self.line(&num(diameter));
                    }
                    Section::General {
                        area,
                        iyy,
                        izz,
                        torsion,
                        shear_coefficient,
                    } => {
                        if shear_coefficient == 0.0 {
                            self.comment("A (mm^2), I1, I2, J (mm^4)");
                            self.line(&nums([area, iyy, izz, torsion]));
                        } else {
                            self.comment("A (mm^2), I1, I2, J (mm^4), shear coefficient");
                            self.line(&nums([area, iyy, izz, torsion, shear_coefficient]));
                        }
                    }
                }
                self.comment("orientation vector (global x, y, z)");
                self.line(&nums(g.orientation));
                self.comment("elements");
                self.list(&g.elements, &element_sets);
            }
        }

        if !m.damping.is_empty() {
            self.line("DAMPING");
            for d in &m.damping {
                let with_nodes = !d.mass_nodes.is_empty();
                self.comment("alpha (1/s), beta (s), 1 if a line of point-mass nodes follows");
                self.line(&format!(
                    "{}, {}",
                    nums([d.alpha, d.beta]),
                    u8::from(with_nodes)
                ));
                self.comment("elements (a blank line: none)");
                self.list(&d.elements, &element_sets);
                if with_nodes {
                    self.comment("nodes whose point masses get alpha");
                    self.list(&d.mass_nodes, &node_sets);
                }
            }
        }
        if !m.beam_tensions.is_empty() {
            self.line("BEAM TENSION");
            for t in &m.beam_tensions {
                self.comment("axial force (N)");
                self.line(&nums([t.force]));
                self.comment("elements");
                self.list(&t.elements, &element_sets);
            }
        }
        if !m.tension_links.is_empty() {
            self.line("TENSION LINK");
            self.comment("node a, node b, dof, stiffness (N/mm), slack (mm)");
            for l in &m.tension_links {
                self.line(&format!(
                    "{}, {}, {}, {}",
                    l.nodes[0],
                    l.nodes[1],
                    l.dof,
                    nums([l.stiffness, l.slack])
                ));
            }
        }
        if !m.moving_contacts.is_empty() {
            self.line("MOVING CONTACT");
            for c in &m.moving_contacts {
                self.comment("head, dof, stiffness (N/mm), speed (mm/s), start (mm)");
                self.line(&format!(
                    "{}, {}, {}",
                    c.head,
                    c.dof,
                    nums([c.stiffness, c.speed, c.start])
                ));
                self.comment("the line's nodes");
                self.list(&c.line, &node_sets);
            }
        }
    }

    /// Point masses, point laws, dashpots, modal damping and rigid ties.
    fn attachments(&mut self) {
        let m = self.model;
        let node_sets = node_sets(m);
        self.out.push_str(&dmig_card(&m.matrix_elements));
        if !m.point_masses.is_empty() {
            self.line("POINT MASS");
            self.comment("node, mass (t), Ixx, Iyy, Izz (t mm^2)");
            for p in &m.point_masses {
                self.line(&format!(
                    "{}, {}",
                    p.node,
                    nums([p.mass, p.inertia[0], p.inertia[1], p.inertia[2]])
                ));
            }
        }

        // One card per kind; an element with every value zero is kept as a zero
        // friction line so that it reads back.
        let cards: [(&str, &str, PointValue); 3] = [
            ("FRICTION", "node, dof, friction force (N)", |e| {
                (e.friction != 0.0 || e.law().is_zero()).then_some(e.friction)
            }),
            ("QUADRATIC DAMPER", "node, dof, c2 (N s^2/mm^2)", |e| {
                (e.quadratic != 0.0).then_some(e.quadratic)
            }),
            ("CUBIC SPRING", "node, dof, k3 (N/mm^3)", |e| {
                (e.cubic != 0.0).then_some(e.cubic)
            }),
        ];
        for (card, units, value) in cards {
            let lines: Vec<String> = m
                .point_laws
                .iter()
                .filter_map(|e| value(e).map(|x| format!("{}, {}, {}", e.node, e.dof, num(x))))
                .collect();
            if !lines.is_empty() {
                self.line(card);
                self.comment(units);
                for l in &lines {
                    self.line(l);
                }
            }
        }

        if !m.dashpots.is_empty() {
            self.line("DASHPOT");
            self.comment("node, dof, c (N s/mm)");
            for d in &m.dashpots {
                self.line(&format!("{}, {}, {}", d.node, d.dof, num(d.c)));
            }
        }
        let md = &m.modal_damping;
        if md.loss_factor_modes > 0 {
            self.line("LOSS FACTOR");
            self.comment("eta (-), modes carrying it in direct integration");
            self.line(&format!(
                "{}, {}",
                num(md.loss_factor),
                md.loss_factor_modes
            ));
        }
        if md.ratios.iter().any(|&z| z != 0.0) {
            self.line("MODAL DAMPING");
            self.comment("mode, zeta");
            for (i, &z) in md.ratios.iter().enumerate() {
                if z != 0.0 {
                    self.line(&format!("{}, {}", i + 1, num(z)));
                }
            }
        }

        if !m.rigid_ties.is_empty() {
            self.line("RBE2");
            for (k, t) in m.rigid_ties.iter().enumerate() {
                self.comment("id, name");
                self.line(&format!("{}, {}", k + 1, t.name));
                self.comment("reference node, tied DOFs");
                let dofs: Vec<String> = t.dofs.iter().map(u8::to_string).collect();
                self.line(&format!("{}, {}", t.reference, dofs.join(", ")));
                self.comment("tied nodes");
                self.list(&t.tied, &node_sets);
            }
        }
    }

    /// Supports, loads, initial velocities and outputs; ends the model definition.
    fn loads_and_outputs(&mut self) {
        let m = self.model;
        let node_sets = node_sets(m);
        if !m.fixed_disp.is_empty() {
            self.line("FIXED DISP");
            for f in &m.fixed_disp {
                self.dof_values("prescribed values (mm, rad)", &f.dofs, &f.nodes, &node_sets);
            }
        }

        for p in &m.point_loads {
            self.point_load(p, &node_sets);
        }

        // One card per run of groups with the same option, so the groups read back in
        // their order and with their option.
        let mut previous: Option<bool> = None;
        for v in &m.initial_velocities {
            if previous != Some(v.quasi_static) {
                self.line(if v.quasi_static {
                    "INITIAL VEL, QUASI STATIC"
                } else {
                    "INITIAL VEL"
                });
                previous = Some(v.quasi_static);
            }
            self.dof_values(
                "initial velocities (mm/s, rad/s)",
                &v.dofs,
                &v.nodes,
                &node_sets,
            );
        }

        if !m.outputs.is_empty() {
            self.line("HISTORY OUTPUT");
            for o in &m.outputs {
                self.comment("every k-th step");
                self.line(&o.every.to_string());
                self.comment("quantities");
                let q: Vec<&str> = o
                    .quantities
                    .iter()
                    .map(|q| match q {
                        Quantity::Displacement => "DISP",
                        Quantity::Velocity => "VEL",
                        Quantity::Acceleration => "ACCEL",
                    })
                    .collect();
                self.line(&q.join(", "));
                self.comment("DOFs");
                let dofs: Vec<String> = o.dofs.iter().map(u8::to_string).collect();
                self.line(&dofs.join(", "));
                self.comment("nodes");
                self.list(&o.nodes, &node_sets);
            }
        }
        self.line("END OPTION");
    }

    fn dof_values(
        &mut self,
        what: &str,
        dofs: &[(u8, f64)],
        nodes: &[u32],
        sets: &[(&str, &[u32])],
    ) {
        self.comment(what);
        self.line(&nums(dofs.iter().map(|d| d.1)));
        self.comment("DOFs");
        let numbers: Vec<String> = dofs.iter().map(|d| d.0.to_string()).collect();
        self.line(&numbers.join(", "));
        self.comment("nodes");
        self.list(nodes, sets);
    }

    fn point_load(&mut self, p: &PointLoad, sets: &[(&str, &[u32])]) {
        match &p.table {
            Some(t) => self.line(&format!("POINT LOAD, TABLE, {t}")),
            None => self.line("POINT LOAD"),
        }
        let last = p
            .dofs
            .iter()
            .map(|d| d.0)
            .filter(|d| (1..=6).contains(d))
            .max()
            .unwrap_or(1);
        let mut values = vec![0.0; usize::from(last)];
        for &(d, v) in &p.dofs {
            if let Some(slot) = values.get_mut(usize::from(d).wrapping_sub(1)) {
                *slot = v;
            }
        }
        self.comment("Fx, Fy, Fz (N), Mx, My, Mz (N mm)");
        self.line(&nums(values));
        self.comment("nodes");
        self.list(&p.nodes, sets);
    }

    fn history(&mut self) {
        let m = self.model;
        let node_sets = node_sets(m);
        for (k, case) in m.load_cases.iter().enumerate() {
            self.rule(&format!("load case {}", k + 1));
            if !case.title.is_empty() {
                self.line(&format!("TITLE, {}", one_line(&case.title)));
            }
            match case.analysis {
                Analysis::Static { steps, time } => {
                    self.line("AUTO LOAD");
                    self.comment("number of steps");
                    self.line(&steps.to_string());
                    self.line("TIME STEP");
                    self.comment("time of each step (s)");
                    self.line(&num(time));
                }
                Analysis::Modal { modes } => {
                    self.line("MODAL SHAPE");
                    self.comment("number of modes");
                    self.line(&modes.to_string());
                }
                Analysis::Transient {
                    dt,
                    total_time,
                    method,
                } => {
                    self.line("DYNAMIC CHANGE");
                    self.comment("dt (s), total time (s), method");
                    let method = match method {
                        TransientMethod::Direct(Integrator::AverageAcceleration) => {
                            "NEWMARK".to_string()
                        }
                        TransientMethod::Direct(Integrator::Hht { alpha }) => {
                            format!("HHT, {}", num(alpha))
                        }
                        TransientMethod::Direct(Integrator::GeneralizedAlpha { rho_inf }) => {
                            format!("GALPHA, {}", num(rho_inf))
                        }
                        TransientMethod::Modal { modes } => format!("MODAL, {modes}"),
                    };
                    self.line(&format!("{}, {method}", nums([dt, total_time])));
                }
            }
            for p in &case.point_loads {
                self.point_load(p, &node_sets);
            }
            self.line("CONTINUE");
        }
    }
}

/// Writes a model in Marc's extended fixed format (parameter `EXTENDED`), the format
/// Mentat writes: keyword lines as a 20-column keyword then 10-column integers or
/// 20-column words, data lines of numbers as 10-column integers and 20-column reals
/// (Rust's shortest round-trip form, right-aligned, so the deck reads back to an
/// equal model). Lines that hold words (names, methods) or a real longer than 19
/// characters stay in free format with commas, which Marc reads line by line too;
/// lists are free format in every Marc format. Cards are the ones [`write`] emits, so
/// the round trip is the same.
pub fn write_mentat(model: &Model) -> String {
    let free = write(model);
    let mut out = String::new();
    let mut extended = false;
    for line in free.lines() {
        let line = &line.replace(
            "in MSC Marc's free format",
            "in MSC Marc's extended fixed format (as Mentat writes)",
        );
        let fixed = to_fixed(line);
        out.push_str(fixed.as_deref().unwrap_or(line));
        out.push('\n');
        if !extended && !line.trim_start().starts_with('$') {
            // EXTENDED right after the first card (TITLE), as Mentat writes it.
            out.push_str(
                "$ Marc's extended fixed format: integers in 10 columns, reals and words in 20\n",
            );
            out.push_str("EXTENDED\n");
            extended = true;
        }
    }
    out
}

/// A free-format line of [`write`] in extended fixed columns, if it can be.
fn to_fixed(line: &str) -> Option<String> {
    if line.trim_start().starts_with('$') || !line.contains(',') {
        return None;
    }
    let parts: Vec<&str> = line.split(',').map(str::trim).collect();
    let int = |s: &str| !s.is_empty() && s.chars().all(|c| c.is_ascii_digit());
    let real = |s: &str| s.parse::<f64>().is_ok() && s.len() <= 19;
    let first = parts[0];
    let mut out = String::new();
    let rest = if first.starts_with(|c: char| c.is_ascii_alphabetic()) {
        // A keyword line: the keyword, then integers or words (TITLE keeps its text).
        if first.eq_ignore_ascii_case("TITLE") || first.len() > 20 {
            return None;
        }
        let _ = write!(out, "{first:<20}");
        &parts[1..]
    } else {
        &parts[..]
    };
    for (k, p) in rest.iter().enumerate() {
        // SIZING's first field (memory) is two integer fields wide.
        if k == 0 && first.eq_ignore_ascii_case("SIZING") && int(p) {
            let _ = write!(out, "{p:>20}");
        } else if int(p) {
            let _ = write!(out, "{p:>10}");
        } else if p.parse::<f64>().is_ok() {
            if !real(p) {
                return None;
            }
            let _ = write!(out, "{p:>20}");
        } else if crate::deck::lexer::is_name(p) && !first.starts_with(char::is_numeric) {
            let _ = write!(out, "{p:<20}");
        } else {
            return None;
        }
    }
    Some(out.trim_end().to_string())
}
