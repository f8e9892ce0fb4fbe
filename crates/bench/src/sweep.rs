//! Sweep files: parameter grids per technique, expanded to the parameter sets `aograph bench`
//! runs.
//!
//! ```toml
//! [hbao]                      # one grid: the cartesian product of its arrays
//! directions = [4, 8, 16]
//! steps = [4, 8, 10]          # 9 parameter sets
//!
//! [[pyramid-hbao]]            # an array of tables: the union of several grids
//! levels = [1, 2, 3, 4, 5]
//! [[pyramid-hbao]]
//! levels = 4
//! directions = [4, 16]
//! ```
//!
//! In a grid an array is the values to try and anything else is held fixed (an array-valued
//! parameter is written as an array of one array). Each set is checked by its technique
//! before any GPU work, so a typo fails at once with the technique's own message. A section
//! naming a technique that is not registered (techniques are added over time) is skipped with
//! a warning naming the nearest registered one, so shipped sweeps keep working as the registry
//! grows; asking for an unknown technique with `--techniques` is an error.

use std::collections::BTreeMap;
use std::path::Path;

use aograph_ao_passes::{TechniqueRegistry, nearest};

use aograph_app_config::error::{AppError, AppResult};

/// One technique with one set of parameters (empty = the technique's defaults).
#[derive(Clone, Debug, PartialEq)]
pub struct ParamSet {
    /// The technique's registry name.
    pub technique: String,
    /// Parameter values by name, as the technique's parameter table in a config takes them;
    /// empty: the technique's defaults.
    pub params: toml::Table,
}

impl ParamSet {
    /// `technique` with no parameter set: its defaults (labelled `defaults`).
    pub fn defaults(technique: &str) -> Self {
        Self {
            technique: technique.into(),
            params: toml::Table::new(),
        }
    }
    /// "directions=8 steps=10", or "defaults".
    pub fn label(&self) -> String {
        if self.params.is_empty() {
            return "defaults".into();
        }
        self.params
            .iter()
            .map(|(k, v)| format!("{k}={v}"))
            .collect::<Vec<_>>()
            .join(" ")
    }
    /// A file-name-safe form of technique and label.
    pub fn slug(&self) -> String {
        let raw = format!("{}_{}", self.technique, self.label());
        raw.chars()
            .map(|c| {
                if c.is_ascii_alphanumeric() || c == '-' || c == '.' {
                    c
                } else {
                    '_'
                }
            })
            .collect::<String>()
            .trim_matches('_')
            .to_string()
    }
}

/// A parsed sweep file: technique name to its grids, in file order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Sweep {
    /// Technique name to its grids, each a table of parameter to value or array of values to
    /// try: one grid for a `[technique]` table, one per entry for `[[technique]]`, in file
    /// order.
    pub grids: BTreeMap<String, Vec<toml::Table>>,
    /// Where it came from, for messages.
    pub source: String,
}

fn err(source: &str, message: String) -> AppError {
    AppError::Config {
        path: source.into(),
        message,
    }
}

impl Sweep {
    /// Reads and parses the sweep file at `path`; errors name the path.
    pub fn load(path: &Path) -> AppResult<Self> {
        let text =
            std::fs::read_to_string(path).map_err(|e| AppError::io("read sweep", path, e))?;
        Self::parse(&text, &path.display().to_string())
    }

    /// Parses sweep text; `source` names it in errors. Technique names and parameters are not
    /// checked here: [`Sweep::registered_techniques`] and [`plan_param_sets`] do that.
    pub fn parse(text: &str, source: &str) -> AppResult<Self> {
        let doc: toml::Table = text
            .parse()
            .map_err(|e: toml::de::Error| err(source, e.to_string().trim().to_string()))?;
        let mut grids = BTreeMap::new();
        for (technique, v) in doc {
            let tables = match v {
                toml::Value::Table(t) => vec![t],
                toml::Value::Array(a) => a
                    .into_iter()
                    .map(|g| match g {
                        toml::Value::Table(t) => Ok(t),
                        _ => Err(err(
                            source,
                            format!("[[{technique}]] entries must be tables of parameters"),
                        )),
                    })
                    .collect::<AppResult<Vec<_>>>()?,
                _ => {
                    return Err(err(
                        source,
                        format!(
                            "`{technique}` must be a table ([{technique}]) or an array of tables ([[{technique}]]) of parameter grids"
                        ),
                    ));
                }
            };
            grids.insert(technique, tables);
        }
        Ok(Self {
            grids,
            source: source.into(),
        })
    }

    /// Every parameter set of `technique`: the union of its grids' cartesian products, first
    /// occurrence kept; one default set when the sweep does not name it.
    pub fn expand(&self, technique: &str) -> Vec<ParamSet> {
        let Some(grids) = self.grids.get(technique) else {
            return vec![ParamSet::defaults(technique)];
        };
        let mut out: Vec<ParamSet> = Vec::new();
        for grid in grids {
            let mut sets = vec![toml::Table::new()];
            for (key, value) in grid {
                let choices = match value {
                    toml::Value::Array(a) => a.clone(),
                    v => vec![v.clone()],
                };
                sets = sets
                    .iter()
                    .flat_map(|s| {
                        choices.iter().map(move |c| {
                            let mut s = s.clone();
                            s.insert(key.clone(), c.clone());
                            s
                        })
                    })
                    .collect();
            }
            for params in sets {
                let set = ParamSet {
                    technique: technique.into(),
                    params,
                };
                if !out.contains(&set) {
                    out.push(set);
                }
            }
        }
        out
    }

    /// Techniques the sweep names that `registry` holds, warning (on stderr) about the rest.
    pub fn registered_techniques(&self, registry: &TechniqueRegistry) -> AppResult<Vec<String>> {
        let names = registry.names();
        let mut known = Vec::new();
        for t in self.grids.keys() {
            if names.contains(t) {
                known.push(t.clone());
            } else {
                // An unknown name is a mistake to fix, not a grid to skip silently: the run
                // would measure less than the sweep says.
                let hint = nearest(t, names.iter().map(String::as_str))
                    .map(|n| format!("did you mean `{n}`? "))
                    .unwrap_or_default();
                return Err(AppError::Config {
                    path: self.source.clone(),
                    message: format!(
                        "technique `{t}` is not registered; {hint}registered: {}",
                        names.join(", ")
                    ),
                });
            }
        }
        Ok(known)
    }
}

/// The parameter sets to run: `techniques` (registry names, already chosen by the caller)
/// with the sweep's grids where it has one, each set validated by its technique.
pub fn plan_param_sets(
    registry: &TechniqueRegistry,
    techniques: &[String],
    sweep: Option<&Sweep>,
) -> AppResult<Vec<ParamSet>> {
    let mut out = Vec::new();
    for t in techniques {
        let technique = registry.get(t)?;
        let sets = sweep
            .map(|s| s.expand(t))
            .unwrap_or_else(|| vec![ParamSet::defaults(t)]);
        for set in sets {
            technique.check(&set.params).map_err(|e| {
                err(
                    sweep.map(|s| s.source.as_str()).unwrap_or("sweep"),
                    format!("{} ({})", e, set.label()),
                )
            })?;
            out.push(set);
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_table_is_a_cartesian_product_and_an_array_of_tables_a_union() {
        let s = Sweep::parse("[hbao]\ndirections = [4, 8, 16]\nsteps = [4, 8, 10]\nattenuation = 0.5\n\n[[p]]\nlevels = [1, 2]\n[[p]]\nlevels = [2, 3]\nd = 4\n", "test").unwrap();
        let h = s.expand("hbao");
        assert_eq!(h.len(), 9);
        assert!(
            h.iter()
                .all(|p| p.params["attenuation"].as_float() == Some(0.5))
        );
        assert_eq!(h[0].label(), "attenuation=0.5 directions=4 steps=4");
        let p = s.expand("p");
        let labels: Vec<String> = p.iter().map(ParamSet::label).collect();
        assert_eq!(
            labels,
            ["levels=1", "levels=2", "d=4 levels=2", "d=4 levels=3"]
        );
        assert_eq!(s.expand("other"), vec![ParamSet::defaults("other")]);
        assert_eq!(ParamSet::defaults("none").label(), "defaults");
        assert_eq!(h[0].slug(), "hbao_attenuation_0.5_directions_4_steps_4");
    }

    #[test]
    fn duplicates_are_run_once_and_bad_files_say_why() {
        let s = Sweep::parse("[[t]]\nn = [1, 2]\n[[t]]\nn = [2, 3]\n", "x").unwrap();
        assert_eq!(s.expand("t").len(), 3);
        assert!(
            Sweep::parse("t = 3", "x")
                .unwrap_err()
                .to_string()
                .contains("must be a table")
        );
        assert!(Sweep::parse("[t\n", "x").is_err());
    }

    #[test]
    fn shipped_sweeps_parse_and_an_unregistered_technique_is_an_error() {
        let registry = TechniqueRegistry::with_builtins();
        for f in ["pyramid-hbao-paper.toml", "quick.toml"] {
            let s = Sweep::load(
                &Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
                    .join("configs/sweeps")
                    .join(f),
            )
            .unwrap();
            let known = s.registered_techniques(&registry).unwrap();
            assert!(known.iter().all(|t| registry.get(t).is_ok()));
            plan_param_sets(&registry, &known, Some(&s)).unwrap();
        }
        let paper = Sweep::load(
            &Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
                .join("configs/sweeps/pyramid-hbao-paper.toml"),
        )
        .unwrap();
        assert_eq!(paper.expand("hbao").len(), 4, "the paper's four D x S rows");
        assert_eq!(paper.expand("pyramid-hbao").len(), 5, "L = 1..5");
        let typo = Sweep::parse("[hbaoo]\ndirections = [8]\n", "typo.toml").unwrap();
        let e = typo
            .registered_techniques(&registry)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("typo.toml") && e.contains("`hbaoo`") && e.contains("did you mean `hbao`"),
            "{e}"
        );
    }

    #[test]
    fn a_bad_parameter_is_caught_before_the_gpu_runs() {
        let registry = TechniqueRegistry::with_builtins();
        let s = Sweep::parse("[none]\nbogus = [1, 2]\n", "bad.toml").unwrap();
        let e = plan_param_sets(&registry, &["none".to_string()], Some(&s))
            .unwrap_err()
            .to_string();
        assert!(e.contains("bad.toml") && e.contains("bogus"), "{e}");
    }
}
