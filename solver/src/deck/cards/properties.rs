//! Element properties: `ISOTROPIC` (E in MPa, Poisson's ratio, density in t/mm^3) and
//! `GEOMETRY` (the beam section in mm and its orientation vector), in coil's layout
//! and Mentat's.
//!
//! Each card is one [`Keyword`] entry (its name, sections, meaning, layout, example
//! and parse function) followed by its parse function; then the family's build function
//! (raw deck -> model parts, run in order by [`crate::deck::build`]); its tests close
//! the file.

use crate::deck::card::{
    another, no_groups, plural, qualifier, CardCtx, DeckSection, Keyword, Origin,
};
use crate::deck::error::{DeckError, Loc};
use crate::deck::lexer::{self, ListItem};
use crate::deck::raw::{RawDeck, RawGeometry, RawMaterial, SetKind};
use crate::deck::resolve::Builder;
use crate::model::Section;
use crate::model::{Geometry, Material, ModelParts};
use DeckSection::Model;

use super::mentat;
/// The `ISOTROPIC` card.
pub(crate) const ISOTROPIC: Keyword = Keyword {
    name: "ISOTROPIC",
    sections: &[Model],
    origin: Origin::Marc,
    meaning: "Linear isotropic elastic materials: Young's modulus, Poisson's ratio and \
              density, and the elements each applies to.",
    layout: &[
        ("ISOTROPIC", ""),
        (
            "n",
            "number of materials; 0 or blank = materials until the next card",
        ),
        (
            "id[, name]",
            "per material: a positive id and a name (the id if omitted)",
        ),
        (
            "E, nu, density[, 0 ...]",
            "E > 0 (MPa), -1 < nu < 0.5, density >= 0 (t/mm^3); Marc's further fields \
             (thermal expansion, yield stress, ...) must be blank or 0",
        ),
        ("list", "the elements"),
    ],
    notes: "Lines 3 to 5 repeat for each material. The id/name line is coil's reading \
            of Marc's material line: coil takes only the id and the name. Where lists \
            overlap, the later material wins.",
    example: "ISOTROPIC\n1\n1, steel\n190708.0, 0.3, 7.85e-9\nwire",
    parse: parse_isotropic,
};

/// The `GEOMETRY` card.
pub(crate) const GEOMETRY: Keyword = Keyword {
    name: "GEOMETRY",
    sections: &[Model],
    origin: Origin::Marc,
    meaning: "Beam cross-sections and orientations, and the elements each applies to.",
    layout: &[
        ("GEOMETRY", ""),
        (
            "n",
            "number of geometries; 0 or blank = geometries until the next card",
        ),
        (
            "[id, name]",
            "optional, per geometry: a positive id and a name",
        ),
        (
            "d   or   A, I1, I2, J[, kappa]",
            "section: a solid circular wire of diameter d (mm), or area A (mm^2), \
             second moments I1 about the orientation direction and I2 about the third \
             axis (Marc's Ixx, Iyy; mm^4), torsion constant J (mm^4) and the \
             Timoshenko shear coefficient kappa (shear area kappa A), all > 0",
        ),
        (
            "vx, vy, vz",
            "orientation vector (global): local x runs along the element, local y is \
             the part of this vector normal to it, local z = x cross y",
        ),
        ("list", "the elements"),
    ],
    notes: "Lines 3 to 6 repeat for each geometry; line 3 is recognised by its second \
            field being a name. coil's own parts: the diameter form, J and kappa as fields (no Ixx + Iyy \
            default for J), and the optional name line. kappa is needed when a listed \
            element is of type 98; type 52 ignores it (recorded as 0 when omitted). \
            The orientation may not be parallel to any listed element \
            (|v x e| <= 1e-6 |v| |e|). I1 becomes the model's iyy, I2 its izz.",
    example: "GEOMETRY\n1\n1, wire\n3.0\n0.0, 0.0, 1.0\nwire",
    parse: parse_geometry,
};

fn parse_isotropic(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    const NAME_LINE: &str = "id, name";
    qualifier(c, "STRUCTURAL")?;
    let header = c.data_line("the number of materials (0 = until the next card)")?;
    if header.fixed.is_none() {
        c.field_count(header, 0, 1, "the number of materials")?;
    }
    let n = c.uint_or(header, 0, 0, "the number of materials")?;
    let n = if header.fixed.is_some() && header.fields.len() > 1 {
        0
    } else {
        n
    };
    let mut done = 0;
    while another(c, n, done) {
        let mentat = c.cur.peek_significant().is_some_and(|l| {
            l.fixed.is_some() && l.fields.len() > 2 && lexer::is_name(&l.fields[1].text)
        });
        if mentat {
            let material = isotropic_material(c)?;
            c.deck.materials.push(material);
            done += 1;
            continue;
        }
        let l = c.data_line(&format!("the line `{NAME_LINE}` of material {}", done + 1))?;
        c.field_count(l, 1, 2, NAME_LINE)?;
        let id = c.id(l, 0, "the material id")?;
        let name = match l.fields.get(1) {
            Some(f) if !f.text.is_empty() => c.name(l, 1, "the material name")?,
            _ => id.to_string(),
        };
        let [youngs_modulus, poisson, density] = material_values(c)?;
        let elements = c.list("the list of elements")?;
        c.deck.materials.push(RawMaterial {
            id,
            name,
            loc: l.start_loc(),
            youngs_modulus,
            poisson,
            density,
            elements,
        });
        done += 1;
    }
    if done == 0 {
        return Err(no_groups(
            c,
            "a material: id, name / E, nu, density / elements",
        ));
    }
    Ok(())
}

/// The values line of a material, in coil's layout and Mentat's: `E, nu, density`
/// checked, Marc's further fields (thermal expansion, yield stress, ...) blank or 0.
pub(crate) fn material_values(c: &mut CardCtx<'_, '_>) -> Result<[f64; 3], DeckError> {
    const PROPS: &str = "E (MPa), Poisson's ratio, density (t/mm^3)";
    let p = c.data_line(PROPS)?;
    c.field_count(p, 3, usize::MAX, PROPS)?;
    let e = c.real(p, 0, "Young's modulus E (MPa)")?;
    let youngs_modulus = c.positive(e, p.loc_of(0), "Young's modulus E")?;
    let poisson = c.real(p, 1, "Poisson's ratio")?;
    if !(poisson > -1.0 && poisson < 0.5) {
        return Err(c.err(
            p.loc_of(1),
            format!("Poisson's ratio is {poisson:?}"),
            "-1 < Poisson's ratio < 0.5",
        ));
    }
    let rho = c.real(p, 2, "density (t/mm^3)")?;
    let density = c.non_negative(rho, p.loc_of(2), "density")?;
    c.zeros_from(
        p,
        3,
        "Marc's further material data (thermal expansion, yield stress, ...)",
    )?;
    Ok([youngs_modulus, poisson, density])
}

const SECTION_LINE: &str = "the section: wire diameter d, or A, I1, I2, J[, shear coefficient]";

fn parse_geometry(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    c.no_args()?;
    let header = c.data_line("the number of geometries (0 = until the next card)")?;
    if header.fixed.is_none() {
        c.field_count(header, 0, 1, "the number of geometries")?;
    }
    let n = c.uint_or(header, 0, 0, "the number of geometries")?;
    let mut done = 0;
    while another(c, n, done) {
        // Mentat's blocks: a line of 6 or more values, or (version 13+) an integer
        // line before the name line; coil's own lines are shorter or free format.
        let mentat_block = c.cur.peek_significant().is_some_and(|l| {
            l.fixed.is_some()
                && (l.fields.len() >= 6
                    || (l.fields.len() >= 2
                        && l.fields.iter().all(|f| lexer::parse_uint(&f.text).is_ok())))
        });
        if mentat_block {
            let geometry = mentat::geometry_block(c)?;
            c.deck.geometries.push(geometry);
            done += 1;
            continue;
        }
        let first = c.data_line(&format!(
            "geometry {}: `id, name` or {SECTION_LINE}",
            done + 1
        ))?;
        let named = first.fields.len() == 2
            && !first.fields[1].text.is_empty()
            && !lexer::looks_numeric(&first.fields[1].text);
        let (id, name, s) = if named {
            let id = c.id(first, 0, "the geometry id")?;
            let name = c.name(first, 1, "the geometry name")?;
            (Some(id), name, c.data_line(SECTION_LINE)?)
        } else {
            (None, String::new(), first)
        };
        let (section, has_shear_coefficient) =
            match s.fields.len() {
                1 => {
                    let d = c.real(s, 0, "the wire diameter (mm)")?;
                    let diameter = c.positive(d, s.loc_of(0), "the wire diameter")?;
                    (Section::SolidCircle { diameter }, true)
                }
                4 | 5 => {
                    let mut v = [0.0; 5];
                    let names = [
                        "the area A",
                        "I1",
                        "I2",
                        "the torsion constant J",
                        "the shear coefficient",
                    ];
                    for (i, what) in names.iter().enumerate().take(s.fields.len()) {
                        let x = c.real(s, i, what)?;
                        v[i] = c.positive(x, s.loc_of(i), what)?;
                    }
                    let section = Section::General {
                        area: v[0],
                        iyy: v[1],
                        izz: v[2],
                        torsion: v[3],
                        shear_coefficient: v[4],
                    };
                    (section, s.fields.len() == 5)
                }
                k => return Err(c.err(
                    s.loc_of(0),
                    format!("a section line with {k} field{}", plural(k)),
                    "1 field (wire diameter, mm) or 4-5 fields (A, I1, I2, J[, shear coefficient])",
                )),
            };
        let o = c.data_line("the orientation vector vx, vy, vz")?;
        c.field_count(o, 3, 3, "the orientation vector vx, vy, vz")?;
        let orientation = [
            c.real(o, 0, "vx")?,
            c.real(o, 1, "vy")?,
            c.real(o, 2, "vz")?,
        ];
        if orientation.iter().all(|&x| x == 0.0) {
            return Err(c.err(
                o.start_loc(),
                "the orientation vector is zero",
                "a non-zero vector",
            ));
        }
        let elements = c.list("the list of elements")?;
        c.deck.geometries.push(RawGeometry {
            id,
            name,
            loc: first.start_loc(),
            section,
            has_shear_coefficient,
            section_loc: s.start_loc(),
            orientation,
            orientation_loc: o.start_loc(),
            elements,
        });
        done += 1;
    }
    if done == 0 {
        return Err(no_groups(
            c,
            "a geometry: [id, name] / section / orientation / elements",
        ));
    }
    Ok(())
}

/// A Mentat ISOTROPIC material: `id`+`elastic` ... name, the values, an optional line
/// of table ids (all 0), and the element list (blank = every element).
pub(crate) fn isotropic_material(c: &mut CardCtx<'_, '_>) -> Result<RawMaterial, DeckError> {
    let l = c.data_line("the material line: id, type, ..., name")?;
    let id = c.id(l, 0, "the material id")?;
    let kind = &l.fields[1].text;
    if !kind.eq_ignore_ascii_case("elastic") {
        return Err(c.err(
            l.loc_of(1),
            format!("material type `{kind}` is not supported"),
            "elastic (coil models linear elastic isotropic materials only)",
        ));
    }
    let last = l.fields.len() - 1;
    let name = if lexer::is_name(&l.fields[last].text) && last > 1 {
        l.fields[last].text.clone()
    } else {
        id.to_string()
    };
    let [e, nu, rho] = material_values(c)?;
    // Table ids: a line of integers only (a list line has `to` or a name).
    if let Some(t) = c.cur.peek_significant() {
        let ints = t.fixed.is_some()
            && t.fields.len() > 1
            && t.fields
                .iter()
                .all(|f| !f.text.is_empty() && lexer::parse_uint(&f.text).is_ok());
        if ints {
            let t = c.data_line("the table ids")?;
            c.zeros_from(t, 0, "Marc tables on material data")?;
        }
    }
    let mut elements = c.list("the list of elements (blank = every element)")?;
    if elements.items.is_empty() {
        elements.items.push((ListItem::All, elements.loc));
    }
    Ok(RawMaterial {
        id,
        name,
        loc: l.start_loc(),
        youngs_modulus: e,
        poisson: nu,
        density: rho,
        elements,
    })
}

/// Materials and geometries: unique names and ids, element lists resolved.
pub(crate) fn build(
    b: &Builder<'_>,
    raw: &RawDeck,
    parts: &mut ModelParts,
) -> Result<(), DeckError> {
    b.unique(
        "ISOTROPIC",
        "material name",
        raw.materials.iter().map(|m| (m.name.as_str(), m.loc)),
    )?;
    let ids: Vec<String> = raw.materials.iter().map(|m| m.id.to_string()).collect();
    b.unique(
        "ISOTROPIC",
        "material id",
        ids.iter()
            .map(String::as_str)
            .zip(raw.materials.iter().map(|m| m.loc)),
    )?;
    for m in &raw.materials {
        let list = b.resolve(&m.elements, SetKind::Element, "ISOTROPIC")?;
        let elements = b.non_empty(list, &m.elements, "ISOTROPIC", "elements")?;
        parts.materials.push(Material {
            name: m.name.clone(),
            youngs_modulus: m.youngs_modulus,
            poisson: m.poisson,
            density: m.density,
            elements,
        });
    }
    b.unique(
        "GEOMETRY",
        "geometry name",
        raw.geometries
            .iter()
            .filter(|g| !g.name.is_empty())
            .map(|g| (g.name.as_str(), g.loc)),
    )?;
    let gids: Vec<(String, Loc)> = raw
        .geometries
        .iter()
        .filter_map(|g| g.id.map(|i| (i.to_string(), g.loc)))
        .collect();
    b.unique(
        "GEOMETRY",
        "geometry id",
        gids.iter().map(|(s, l)| (s.as_str(), *l)),
    )?;
    for g in &raw.geometries {
        let list = b.resolve(&g.elements, SetKind::Element, "GEOMETRY")?;
        let elements = b.non_empty(list, &g.elements, "GEOMETRY", "elements")?;
        parts.geometries.push(Geometry {
            name: g.name.clone(),
            section: g.section.clone(),
            orientation: g.orientation,
            elements,
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::deck::cards::testing::*;

    #[test]
    fn isotropic_values_are_checked() {
        let m = with_model("").unwrap();
        assert_eq!(m.materials[0].name, "steel");
        assert_eq!(m.materials[0].youngs_modulus, 2.0e5);
        assert_eq!(m.materials[0].elements, [1, 2]);
        for (bad, what) in [
            ("0.0, 0.3, 7.85e-9", "Young's modulus"),
            ("2e5, 0.5, 0", "Poisson"),
            ("2e5, -1, 0", "Poisson"),
            ("2e5, 0.3, -1e-9", "density"),
            ("2e5, 0.3, 0, 1.2e-5", "thermal expansion"),
        ] {
            let deck = format!(
                "{PARAMS}{}{STATIC}",
                MESH.replace("2.0e5, 0.3, 7.85e-9", bad)
            );
            let e = read_str(&deck, "t.dat").unwrap_err().to_string();
            assert!(e.contains(":18:") && e.contains(what), "{bad}: {e}");
        }
    }

    #[test]
    fn geometry_forms() {
        let m = with_model("").unwrap();
        assert_eq!(
            m.geometries[0].section,
            Section::SolidCircle { diameter: 3.0 }
        );
        assert_eq!(m.geometries[0].name, "");
        let general = MESH.replace(
            "GEOMETRY\n1\n3.0\n",
            "GEOMETRY\n1\n7, g\n7.0, 4.0, 5.0, 9.0, 0.9\n",
        );
        let m = read_str(&format!("{PARAMS}{general}{STATIC}"), "t.dat").unwrap();
        assert_eq!(m.geometries[0].name, "g");
        assert_eq!(
            m.geometries[0].section,
            Section::General {
                area: 7.0,
                iyy: 4.0,
                izz: 5.0,
                torsion: 9.0,
                shear_coefficient: 0.9
            }
        );
        // Without kappa a type-98 element has no shear coefficient.
        let no_kappa = MESH.replace("GEOMETRY\n1\n3.0\n", "GEOMETRY\n1\n7.0, 4.0, 5.0, 9.0\n");
        let e = read_str(&format!("{PARAMS}{no_kappa}{STATIC}"), "t.dat")
            .unwrap_err()
            .to_string();
        assert!(e.contains("shear coefficient"), "{e}");
        let parallel = MESH.replace("0, 0, 1\nwire", "2, 0, 0\nwire");
        let e = read_str(&format!("{PARAMS}{parallel}{STATIC}"), "t.dat")
            .unwrap_err()
            .to_string();
        assert!(e.contains("parallel"), "{e}");
    }
}
