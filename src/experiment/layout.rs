//! Where an experiment's results lie in its output folder: the one place of every path and file
//! name, so that the plan, its stages, the merge of its commands' results and the table agree.
//!
//! ```text
//! OUT_DIR/paper_table.md, paper_table.json     the table
//! OUT_DIR/index.html                           the table and the plots in one page
//! OUT_DIR/original/SPACE-Pkg.json              the original design's solve at payload P
//! OUT_DIR/runs/NAME.json (+ NAME.log.jsonl)    each co-design run ([`RunName`])
//! OUT_DIR/capacity/SPACE-original.json         the original design's payload capacity
//! OUT_DIR/capacity/SPACE-Pkg-best.json         the capacity of a case's best design
//! OUT_DIR/plots/original-SPACE-Pkg/, best-SPACE-Pkg/, cost_evolution-SPACE-Pkg.svg,
//!               optimal_ratios.svg             the plots
//! OUT_DIR/hold/                                the hold section, laid out the same way
//! ```

use codesign_core::problem::Space;
use std::fmt;
use std::path::{Path, PathBuf};

/// The folders of a results folder, created before its stages run.
pub const FOLDERS: [&str; 4] = ["original", "runs", "plots", "capacity"];

/// The folder of the hold section inside a reproduction's output folder.
pub const HOLD_FOLDER: &str = "hold";

/// The name of a co-design run's result in `runs/` (without `.json`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RunName {
    /// CMA-ES on the cost at a payload (kg), per seed: `SPACE-Pkg-seedN`.
    Cost {
        /// Joint or actuation space.
        space: Space,
        /// Payload, kg.
        payload_kg: f64,
        /// CMA-ES seed.
        seed: u64,
    },
    /// The same with the graded penalty: `SPACE-Pkg-graded-seedN`.
    Graded {
        /// Joint or actuation space.
        space: Space,
        /// Payload, kg.
        payload_kg: f64,
        /// CMA-ES seed.
        seed: u64,
    },
    /// The gradient method at a payload: `SPACE-Pkg-gradient`, or with the graded penalty
    /// `SPACE-Pkg-graded-gradient`.
    Gradient {
        /// Joint or actuation space.
        space: Space,
        /// Payload, kg.
        payload_kg: f64,
        /// With the graded penalty.
        graded: bool,
    },
    /// CMA-ES on the payload capacity: `SPACE-capacity-seed0`.
    Capacity {
        /// Joint or actuation space.
        space: Space,
    },
    /// One design for a payload range (kg, first and last): `SPACE-range-A-Bkg-seed0`.
    Range {
        /// Joint or actuation space.
        space: Space,
        /// The range's first payload, kg.
        first_kg: f64,
        /// Its last payload, kg.
        last_kg: f64,
    },
}

impl fmt::Display for RunName {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            RunName::Cost {
                space,
                payload_kg,
                seed,
            } => write!(f, "{space}-{payload_kg}kg-seed{seed}"),
            RunName::Graded {
                space,
                payload_kg,
                seed,
            } => write!(f, "{space}-{payload_kg}kg-graded-seed{seed}"),
            RunName::Gradient {
                space,
                payload_kg,
                graded,
            } => {
                let graded = if graded { "-graded" } else { "" };
                write!(f, "{space}-{payload_kg}kg{graded}-gradient")
            }
            RunName::Capacity { space } => write!(f, "{space}-capacity-seed0"),
            RunName::Range {
                space,
                first_kg,
                last_kg,
            } => write!(f, "{space}-range-{first_kg}-{last_kg}kg-seed0"),
        }
    }
}

/// Whose payload capacity a capacity file holds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CapacityOf {
    /// The original design's, in a space: `SPACE-original`.
    Original(Space),
    /// The best design's of the co-design at a payload (kg) in a space: `SPACE-Pkg-best`.
    Best(Space, f64),
}

impl CapacityOf {
    /// The space the capacity is searched in.
    pub fn space(self) -> Space {
        match self {
            CapacityOf::Original(space) | CapacityOf::Best(space, _) => space,
        }
    }
}

impl fmt::Display for CapacityOf {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            CapacityOf::Original(space) => write!(f, "{space}-original"),
            CapacityOf::Best(space, payload_kg) => write!(f, "{space}-{payload_kg}kg-best"),
        }
    }
}

/// The layout of one results folder.
#[derive(Clone, Debug, PartialEq)]
pub struct Layout {
    root: PathBuf,
}

impl Layout {
    /// The layout of the results folder `root`.
    pub fn new(root: impl Into<PathBuf>) -> Layout {
        Layout { root: root.into() }
    }

    /// The folder itself.
    pub fn root(&self) -> &Path {
        &self.root
    }

    /// The hold section's folder, laid out the same way.
    pub fn hold(&self) -> Layout {
        Layout::new(self.root.join(HOLD_FOLDER))
    }

    /// Its subfolders ([`FOLDERS`]).
    pub fn folders(&self) -> impl Iterator<Item = PathBuf> + '_ {
        FOLDERS.iter().map(|folder| self.root.join(folder))
    }

    /// The folder of the co-design runs' results and logs.
    pub fn runs(&self) -> PathBuf {
        self.root.join("runs")
    }

    /// The folder of the capacity searches' results.
    pub fn capacities(&self) -> PathBuf {
        self.root.join("capacity")
    }

    /// The folder of the plots.
    pub fn plots(&self) -> PathBuf {
        self.root.join("plots")
    }

    /// The table in Markdown.
    pub fn table_markdown(&self) -> PathBuf {
        self.root.join("paper_table.md")
    }

    /// The table as a result document.
    pub fn table_json(&self) -> PathBuf {
        self.root.join("paper_table.json")
    }

    /// The page of the table and the plots.
    pub fn index(&self) -> PathBuf {
        self.root.join("index.html")
    }

    /// The result of the original design's solve at `payload_kg` in `space`.
    pub fn original(&self, space: Space, payload_kg: f64) -> PathBuf {
        let name = format!("{space}-{payload_kg}kg.json");
        self.root.join("original").join(name)
    }

    /// The plot folder of the original design at `payload_kg` in `space`.
    pub fn original_plots(&self, space: Space, payload_kg: f64) -> PathBuf {
        self.plots()
            .join(format!("original-{space}-{payload_kg}kg"))
    }

    /// The plot folder of the best design of the co-design at `payload_kg` in `space`.
    pub fn best_plots(&self, space: Space, payload_kg: f64) -> PathBuf {
        self.plots().join(format!("best-{space}-{payload_kg}kg"))
    }

    /// The cost evolution of the co-design at `payload_kg` in `space` (the paper's figure 6).
    pub fn cost_evolution(&self, space: Space, payload_kg: f64) -> PathBuf {
        self.plots()
            .join(format!("cost_evolution-{space}-{payload_kg}kg.svg"))
    }

    /// The chart of every case's best ratios (the paper's figure 10).
    pub fn optimal_ratios(&self) -> PathBuf {
        self.plots().join("optimal_ratios.svg")
    }

    /// The result of the co-design run `name`.
    pub fn run(&self, name: &RunName) -> PathBuf {
        self.runs().join(format!("{name}.json"))
    }

    /// The result of the capacity search of `of`.
    pub fn capacity(&self, of: CapacityOf) -> PathBuf {
        self.capacities().join(format!("{of}.json"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The names the committed results carry (`results/quick/`).
    #[test]
    fn names_are_the_committed_results_names() {
        let layout = Layout::new("results/quick");
        let (joint, actuation) = (Space::Joint, Space::Actuation);
        let names = [
            (
                RunName::Cost {
                    space: actuation,
                    payload_kg: 1.0,
                    seed: 0,
                },
                "actuation-1kg-seed0",
            ),
            (
                RunName::Graded {
                    space: joint,
                    payload_kg: 3.0,
                    seed: 1,
                },
                "joint-3kg-graded-seed1",
            ),
            (
                RunName::Gradient {
                    space: joint,
                    payload_kg: 3.0,
                    graded: true,
                },
                "joint-3kg-graded-gradient",
            ),
            (
                RunName::Gradient {
                    space: actuation,
                    payload_kg: 1.0,
                    graded: false,
                },
                "actuation-1kg-gradient",
            ),
            (RunName::Capacity { space: joint }, "joint-capacity-seed0"),
            (
                RunName::Range {
                    space: actuation,
                    first_kg: 1.0,
                    last_kg: 3.0,
                },
                "actuation-range-1-3kg-seed0",
            ),
        ];
        for (name, expected) in names {
            let path = layout.run(&name);
            assert_eq!(
                path,
                PathBuf::from(format!("results/quick/runs/{expected}.json"))
            );
            let committed = Path::new(env!("CARGO_MANIFEST_DIR")).join(&path);
            assert!(committed.exists(), "{}", committed.display());
        }
        let best = layout.hold().capacity(CapacityOf::Best(joint, 1.0));
        assert_eq!(
            best,
            PathBuf::from("results/quick/hold/capacity/joint-1kg-best.json")
        );
        assert_eq!(
            layout.original(actuation, 0.0),
            PathBuf::from("results/quick/original/actuation-0kg.json")
        );
        assert_eq!(
            layout.cost_evolution(joint, 3.0),
            PathBuf::from("results/quick/plots/cost_evolution-joint-3kg.svg")
        );
    }
}
