//! `coil-mesh`: helical spring geometry -> coil input deck.
//!
//! Settings come from an optional JSON spec file (the fields of
//! `coil_mesher::SpringSpec`), then from flags, which override the file.
//! `coil-mesh catenary SPEC.json -o DECK` meshes a pantograph-catenary model instead
//! (`coil_catenary::model`, docs/catenary.md). The binary sits in the command-line crate
//! because that subcommand calls coil-catenary, which is above the mesher.

use clap::{Parser, ValueEnum};
use coil_mesher::{AnalysisKind, SpringSpec, Top, TransientScheme, VelocityField};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Debug, Clone, Copy, ValueEnum)]
enum TopArg {
    Guided,
    FreeRotation,
    Held,
}

#[derive(Debug, Clone, Copy, ValueEnum)]
enum AnalysisArg {
    Static,
    Modal,
    Transient,
}

#[derive(Debug, Clone, Copy, ValueEnum)]
enum FieldArg {
    QuasiStatic,
    Nodal,
}

#[derive(Debug, Clone, Copy, ValueEnum)]
enum MethodArg {
    Newmark,
    Hht,
    Galpha,
    Modal,
}

/// Other models than a spring.
#[derive(Debug, clap::Subcommand)]
enum Mesh {
    /// Mesh a pantograph-catenary model (docs/catenary.md, "The catenary spec"): the
    /// static state (dropper lengths for the presag) is solved first; the deck's STATIC
    /// case is that state with the head pressed on the wire, its transient the run.
    Catenary {
        /// JSON spec: `catenary`, `pantograph`, `run`.
        spec: PathBuf,
        /// Output deck.
        #[arg(short = 'o', long = "output", value_name = "DECK")]
        output: PathBuf,
        /// Also write the static state (dropper forces and lengths, presag miss) as JSON.
        #[arg(long, value_name = "JSON")]
        state: Option<PathBuf>,
    },
}

/// Mesh a helical spring into a coil input deck (mm, N, t, s).
#[derive(Debug, Parser)]
#[command(
    name = "coil-mesh",
    version,
    about,
    args_conflicts_with_subcommands = true,
    subcommand_negates_reqs = true,
    after_help = "Geometry refused (docs/files.md): fewer than 1 coil, a pitch at or below the wire \
diameter (coils through each other), D/d outside [3, 100] (EN 13906-1 recommends 4 to 20 for manufacture). \
The deck is written as a regular file; an existing symlink, device or FIFO at -o is refused."
)]
struct Args {
    #[command(subcommand)]
    mesh: Option<Mesh>,
    /// JSON spec file (fields of SpringSpec); flags override it.
    spec: Option<PathBuf>,
    /// Output deck.
    #[arg(short = 'o', long = "output", value_name = "DECK", required = true)]
    output: Option<PathBuf>,
    /// Deck format: coil's free format, or Marc's extended fixed format as Mentat
    /// writes it (reads back to the same model; see docs/deck.md).
    #[arg(long = "format", value_enum, default_value_t = DeckFormat::Free)]
    format: DeckFormat,
    /// Also write the merged spec as JSON.
    #[arg(long, value_name = "JSON")]
    write_spec: Option<PathBuf>,
    #[arg(long)]
    title: Option<String>,
    /// Number of active coils n.
    #[arg(long, value_name = "N")]
    coils: Option<f64>,
    /// Mean coil diameter D.
    #[arg(long, value_name = "MM")]
    mean_diameter: Option<f64>,
    /// Wire diameter d.
    #[arg(long, value_name = "MM")]
    wire_diameter: Option<f64>,
    /// Pitch h.
    #[arg(long, value_name = "MM")]
    pitch: Option<f64>,
    /// Beam elements per coil [default: 24].
    #[arg(long, value_name = "M")]
    elements_per_coil: Option<u32>,
    /// Marc element type: 98 (Timoshenko) or 52 (Euler-Bernoulli) [default: 98].
    #[arg(long, value_name = "98|52")]
    element: Option<u32>,
    /// Lumped instead of consistent mass.
    #[arg(long)]
    lumped: bool,
    /// Young's modulus E [default: 206000].
    #[arg(long, value_name = "MPA")]
    youngs_modulus: Option<f64>,
    /// Poisson's ratio [default: 0.3].
    #[arg(long)]
    poisson: Option<f64>,
    /// Wire density [default: 7850].
    #[arg(long, value_name = "KG_M3")]
    density: Option<f64>,
    /// Mass of the weight on top [default: 0].
    #[arg(long, value_name = "KG")]
    mass: Option<f64>,
    /// Rotary inertia of the weight about the spring axis (the POINT MASS's Izz)
    /// [default: 0].
    #[arg(long, visible_alias = "weight-inertia-kg-m2", value_name = "KG_M2")]
    rotary_inertia: Option<f64>,
    /// Dry (Coulomb) friction force on the weight's axial motion (N) [default: 0].
    #[arg(long = "friction-n", value_name = "N")]
    friction: Option<f64>,
    /// Velocity-squared drag coefficient c2 on the weight's axial motion, c2 v|v|
    /// (N s^2/m^2) [default: 0].
    #[arg(long = "quadratic-damping-n-s2-m2", value_name = "C2")]
    quadratic_damping: Option<f64>,
    /// Cubic stiffness k3 on the weight's axial displacement from the free length,
    /// k3 u^3 (N/m^3) [default: 0].
    #[arg(long = "cubic-stiffness-n-m3", value_name = "K3")]
    cubic_stiffness: Option<f64>,
    /// How the top reference node is held [default: guided].
    #[arg(long, value_enum)]
    top: Option<TopArg>,
    /// Load cases, in order (repeat or comma-separate) [default: static].
    #[arg(long, value_enum, value_delimiter = ',')]
    analysis: Vec<AnalysisArg>,
    /// Static: compressive axial force on the weight [default: 10].
    #[arg(long, value_name = "N")]
    force: Option<f64>,
    /// Modal: number of modes [default: 10].
    #[arg(long, value_name = "K")]
    modes: Option<u32>,
    /// Transient: time step [default: 0.001].
    #[arg(long, value_name = "S")]
    dt: Option<f64>,
    /// Transient: total time [default: 20].
    #[arg(long, value_name = "S")]
    duration: Option<f64>,
    /// Transient: initial axial velocity of the weight [default: 0.1].
    #[arg(long, value_name = "M_S")]
    initial_velocity: Option<f64>,
    /// Rayleigh alpha on the spring's elements (never on the weight) [default: 0].
    #[arg(long)]
    alpha: Option<f64>,
    /// Rayleigh beta on the spring's elements [default: 0].
    #[arg(long)]
    beta: Option<f64>,
    /// Transient: record every k-th step [default: 1].
    #[arg(long, value_name = "K")]
    output_every: Option<u32>,
    /// Transient: record every node's displacement every k-th step as well, for a
    /// ParaView series of the moving spring (`caseN_transient.pvd`) [default: 0, none].
    #[arg(long, value_name = "K")]
    snapshot_every: Option<u32>,
    /// Transient: the weight's velocity extended along the spring by the quasi-static
    /// shape, or given to the weight alone (a velocity jump) [default: quasi-static].
    #[arg(long, value_enum)]
    initial_velocity_field: Option<FieldArg>,
    /// Transient: Newmark average acceleration, HHT-alpha, generalised-alpha or modal
    /// superposition [default: newmark].
    #[arg(long, value_enum)]
    transient_method: Option<MethodArg>,
    /// Transient, hht: alpha in [-1/3, 0] [default: -0.05].
    #[arg(long, allow_hyphen_values = true)]
    hht_alpha: Option<f64>,
    /// Transient, galpha: spectral radius at infinity in [0, 1] [default: 0.8].
    #[arg(long)]
    rho_inf: Option<f64>,
    /// Transient, modal: number of modes [default: 20].
    #[arg(long, value_name = "K")]
    transient_modes: Option<u32>,
    /// Apply Rayleigh alpha to the weight's mass too (off: the spring's elements only).
    #[arg(long)]
    alpha_on_weight: bool,
}

fn merge(args: &Args, mut spec: SpringSpec) -> SpringSpec {
    macro_rules! set {
        ($($field:ident <- $arg:ident),* $(,)?) => {
            $(if let Some(v) = args.$arg.clone() { spec.$field = v; })*
        };
    }
    set!(
        title <- title,
        coils <- coils,
        mean_diameter_mm <- mean_diameter,
        wire_diameter_mm <- wire_diameter,
        pitch_mm <- pitch,
        elements_per_coil <- elements_per_coil,
        element <- element,
        youngs_modulus_mpa <- youngs_modulus,
        poisson <- poisson,
        density_kg_m3 <- density,
        mass_kg <- mass,
        rotary_inertia_kg_m2 <- rotary_inertia,
        friction_n <- friction,
        quadratic_damping_n_s2_m2 <- quadratic_damping,
        cubic_stiffness_n_m3 <- cubic_stiffness,
        force_n <- force,
        modes <- modes,
        dt_s <- dt,
        duration_s <- duration,
        initial_velocity_m_s <- initial_velocity,
        alpha <- alpha,
        beta <- beta,
        output_every <- output_every,
        snapshot_every <- snapshot_every,
        hht_alpha <- hht_alpha,
        rho_inf <- rho_inf,
        transient_modes <- transient_modes,
    );
    if args.alpha_on_weight {
        spec.alpha_on_weight = true;
    }
    if let Some(field) = args.initial_velocity_field {
        spec.initial_velocity_field = match field {
            FieldArg::QuasiStatic => VelocityField::QuasiStatic,
            FieldArg::Nodal => VelocityField::Nodal,
        };
    }
    if let Some(method) = args.transient_method {
        spec.transient_method = match method {
            MethodArg::Newmark => TransientScheme::Newmark,
            MethodArg::Hht => TransientScheme::Hht,
            MethodArg::Galpha => TransientScheme::Galpha,
            MethodArg::Modal => TransientScheme::Modal,
        };
    }
    if args.lumped {
        spec.lumped_mass = true;
    }
    if let Some(top) = args.top {
        spec.top = match top {
            TopArg::Guided => Top::Guided,
            TopArg::FreeRotation => Top::FreeRotation,
            TopArg::Held => Top::Held,
        };
    }
    if !args.analysis.is_empty() {
        spec.analyses = args
            .analysis
            .iter()
            .map(|a| match a {
                AnalysisArg::Static => AnalysisKind::Static,
                AnalysisArg::Modal => AnalysisKind::Modal,
                AnalysisArg::Transient => AnalysisKind::Transient,
            })
            .collect();
    }
    spec
}

/// The deck formats `coil-mesh` writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum DeckFormat {
    /// coil's free format (commas and blanks).
    Free,
    /// Marc's extended fixed format, as Mentat writes it.
    Mentat,
}

fn catenary(
    spec: &std::path::Path,
    output: &std::path::Path,
    state: Option<&std::path::Path>,
) -> Result<(), String> {
    let spec: coil_catenary::model::CatenaryDeckSpec =
        coil_catenary::model::read_json(spec).map_err(|e| e.to_string())?;
    let built = coil_catenary::model::build(&spec).map_err(|e| e.to_string())?;
    let deck = coil_solver::deck::write(&built.model);
    coil_io::write_file(output, deck.as_bytes()).map_err(|e| e.to_string())?;
    if let Some(path) = state {
        let json = serde_json::to_string_pretty(&built.state).map_err(|e| e.to_string())?;
        coil_io::write_file(path, json.as_bytes()).map_err(|e| e.to_string())?;
    }
    Ok(())
}

fn run(args: &Args) -> Result<(), String> {
    if let Some(Mesh::Catenary {
        spec,
        output,
        state,
    }) = &args.mesh
    {
        return catenary(spec, output, state.as_deref());
    }
    let Some(output) = &args.output else {
        return Err("the output deck is missing: expected -o DECK".into());
    };
    let base = match &args.spec {
        Some(path) => coil_mesher::read_spec(path).map_err(|e| e.to_string())?,
        None => SpringSpec::default(),
    };
    let spec = merge(args, base);
    let model = spec
        .build()
        .map_err(|e| format!("invalid spring spec: {e}"))?;
    let deck = match args.format {
        DeckFormat::Free => coil_solver::deck::write(&model),
        DeckFormat::Mentat => coil_solver::deck::write_mentat(&model),
    };
    coil_io::write_file(output, deck.as_bytes()).map_err(|e| e.to_string())?;
    if let Some(path) = &args.write_spec {
        let json = serde_json::to_string_pretty(&spec).map_err(|e| e.to_string())?;
        coil_io::write_file(path, json.as_bytes()).map_err(|e| e.to_string())?;
    }
    Ok(())
}

fn main() -> ExitCode {
    let args = Args::parse();
    match run(&args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!(
                "coil-mesh: {}",
                coil_io::clean_message(&message.to_string())
            );
            ExitCode::from(2)
        }
    }
}
