//! The rules of a run in a region: its domain (an expression with its box, a shape, or
//! linear constraints and mixtures), the options that mean nothing there, its energy,
//! its points to keep and its start.

use super::Ctx;
use crate::config::{EnergyKind, GenerateConfig, Init, Space};
use crate::domains::Domain;
use crate::pipeline::options::{kind::normal_word, words, Opt, Value};
use crate::pipeline::request::Arg;
use crate::plan::constraints::{Constrained, ConstraintSpec, Mixture};
use crate::plan::space::{numbers_text, RegionSpec};
use crate::{Error, PointSet};
use serde_json::json;
use std::sync::Arc;

/// A region's domain, the mixture whose last component is appended, and the
/// description the report gives of the region.
type RegionParts = (Arc<dyn Domain>, Option<Mixture>, serde_json::Value);

/// The energy of U_{E,p,g} by name; its p is `p`.
const E_P_G: &str = words::REGION_ENERGIES[2];

impl Ctx<'_> {
    /// The polytope of `constraints` and `mixture`, when either is given, with the
    /// constraints' texts.
    fn constrained(
        &self,
        s: Option<usize>,
        bbox: Option<&[f64]>,
    ) -> Result<Option<(Constrained, Vec<String>)>, Error> {
        let mixture = self.p.mixture.value()? == Some(true);
        if !self.given(Opt::constraints) && !mixture {
            return Ok(None);
        }
        let by = if mixture {
            Opt::mixture
        } else {
            Opt::constraints
        };
        if let Some(other) = self.first_of(&[Opt::region, Opt::shape]) {
            return Err(self.refuse(
                other,
                format!(
                    "no {} with {}: the constraints cut the box {} gives",
                    self.name(other),
                    self.name(by),
                    self.name(Opt::bbox)
                ),
            ));
        }
        // A mixture runs in its first S − 1 components: points given in S would not fit.
        let init_points = matches!(self.r.arg(Opt::init), Some(Arg::Points(_)));
        let points = [
            (Opt::extend, self.given(Opt::extend)),
            (Opt::init, init_points),
        ];
        if let (true, Some((other, _))) = (mixture, points.iter().find(|p| p.1)) {
            return Err(self.refuse(
                *other,
                format!(
                    "no {} points with {}: the set is made whole, from a start of its own",
                    self.name(*other),
                    self.name(Opt::mixture)
                ),
            ));
        }
        let texts = self.p.constraints.value()?.unwrap_or_default();
        let built = ConstraintSpec {
            texts: &texts,
            bbox,
            s,
            mixture,
        }
        .build(self.spell)?;
        Ok(Some((built, texts)))
    }

    /// The energy asked for in a region, as a word; the options that mean nothing for a
    /// region's energies are refused, not ignored.
    fn region_energy_word(&self) -> Result<Option<String>, Error> {
        let energy = match self.r.arg(Opt::energy) {
            Some(Arg::Text(t)) => Some(normal_word(t.as_str())),
            Some(other) => {
                return Err(self.bad(Opt::energy, &other, words::listed(&words::REGION_ENERGIES)))
            }
            None => None,
        };
        let is_epg = energy.as_deref() == Some(E_P_G);
        for (o, given, why) in [
            (Opt::q, true, "U_{q,p} is an energy of the cube"),
            (
                Opt::precision,
                true,
                "it sets U_{q,p}'s distance, which region energies do not use",
            ),
            (
                Opt::polish,
                true,
                "the discrepancies it lowers live in the unit cube",
            ),
            (
                Opt::shifts,
                true,
                "a periodic shift would carry points out of the region",
            ),
            (
                Opt::log_every,
                true,
                "it logs the unit cube's discrepancies",
            ),
            (
                Opt::p,
                !is_epg,
                "p belongs to U_{E,p,g} (energy e-p-g) in a region",
            ),
            (
                Opt::nested,
                true,
                "nested sets are made by the integration goal in the cube; grow a region's \
                 set with extend",
            ),
        ] {
            if given && self.given(o) {
                return Err(self.refuse(o, format!("not in a region: {why}")));
            }
        }
        Ok(energy)
    }

    /// The region's domain and the mixture whose last component is appended, with the
    /// description the report gives of the region.
    fn region_domain(&self, s: Option<usize>) -> Result<RegionParts, Error> {
        let bbox = self.p.bbox.value()?;
        let expression = self.p.region.value()?;
        let shape = self.p.shape.value()?;
        let spec = RegionSpec {
            expression: expression.as_deref(),
            bbox: bbox.as_deref(),
            shape: shape.as_deref(),
            s,
        };
        let constrained = self.constrained(s, bbox.as_deref())?;
        let polytope = crate::plan::space::shape::POLYTOPE;
        if bbox.is_some()
            && constrained.is_none()
            && spec.expression.is_none()
            && !spec
                .shape
                .is_some_and(|t| t.starts_with(&format!("{polytope}:")))
        {
            return Err(self.box_alone());
        }
        // The region as the user gave it, under its options' names (the report reads
        // them back by the same names).
        let mut description = json!({"expression": expression});
        description[Opt::bbox.name()] = json!(bbox.as_deref().map(numbers_text));
        description[Opt::shape.name()] = json!(shape);
        Ok(match constrained {
            Some((c, texts)) => {
                description[Opt::constraints.name()] = json!(texts);
                description[Opt::mixture.name()] =
                    json!(c.mixture.as_ref().map(|m| m.components()));
                (c.domain, c.mixture, description)
            }
            None => (spec.domain(self.spell)?, None, description),
        })
    }

    /// The number of points of a region's run: n, or with points to keep (inside the
    /// region, of its dimension) the n to add besides them.
    fn region_n(&self, domain: &dyn Domain, old: Option<&PointSet>) -> Result<usize, Error> {
        let m = self.n_points()?;
        let Some(p) = old else {
            return Ok(m);
        };
        let dim = domain.dim();
        if p.s() != dim {
            return Err(self.refuse(
                Opt::extend,
                format!("points of the region's dimension, {dim}"),
            ));
        }
        if let Some(i) = p.rows().position(|x| !domain.contains(x)) {
            return Err(self.refuse(
                Opt::extend,
                format!(
                    "old points inside the run's region; point {} is outside",
                    i + 1
                ),
            ));
        }
        self.grown(m, p.n())
    }

    /// The start of a region's run: random by default, Halton, or points of the run's
    /// dimension (as many as the points to add).
    fn region_init(&self, cfg: &GenerateConfig, kept: usize, dim: usize) -> Result<Init, Error> {
        Ok(match self.p.init.value()? {
            None => Init::Random,
            Some(Value::Points(p)) => {
                if p.s() != dim || p.n() != cfg.n - kept {
                    return Err(
                        self.refuse(Opt::init, format!("{} points in {dim} dimensions", cfg.n))
                    );
                }
                Init::Points(p)
            }
            Some(Value::Word(w)) if w == words::STARTS[0] => Init::Halton,
            Some(_) => Init::Random,
        })
    }

    /// The configuration of a run in a region, and the mixture whose last component is
    /// appended to its points.
    pub(super) fn region_config(&self) -> Result<(GenerateConfig, Option<Mixture>), Error> {
        let s = self.p.s.value()?;
        let (domain, mixture, description) = self.region_domain(s)?;
        let dim = domain.dim();
        let energy = self.region_energy_word()?;
        let old = self.p.extend.value()?;
        let n = self.region_n(domain.as_ref(), old.as_ref())?;
        let mut cfg = GenerateConfig::in_region(domain, n);
        cfg.space = Space::Region {
            domain: cfg
                .region()
                .cloned()
                .ok_or_else(|| self.absent(Opt::region, "a region"))?,
            description,
        };
        cfg.energy = match energy.as_deref() {
            None | Some("e-inf-g") => EnergyKind::EInfG,
            Some("e-inf") => EnergyKind::EInf,
            Some(E_P_G) => EnergyKind::EpG(self.p.p.value()?.unwrap_or(8.0)),
            Some(_) => {
                return Err(self.refuse(Opt::energy, "in a region e-inf-g (eq. 56), e-inf or e-p-g"))
            }
        };
        cfg.init = self.region_init(&cfg, old.as_ref().map_or(0, |o| o.n()), dim)?;
        cfg.extend = old;
        Ok((cfg, mixture))
    }
}
