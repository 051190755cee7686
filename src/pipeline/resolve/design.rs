//! The rules of a design space, for `generate` and `eval` alike: its variables and the
//! correlation of its continuous ones, the options a design refuses, and the run in the
//! unit cube that is carried into it.

use super::Ctx;
use crate::design::DesignSpace;
use crate::pipeline::measure::cube_rule;
use crate::pipeline::options::{Group, Opt, Value};
use crate::pipeline::request::Resolved;
use crate::Error;

impl Ctx<'_> {
    /// The design space `space` gives, with the correlation of its continuous variables.
    pub(crate) fn design_space(&self) -> Result<DesignSpace, Error> {
        let option = self.name(Opt::space);
        let items = self.p.space.value()?.unwrap_or_default();
        let mut space = DesignSpace::parse(&option, &items)?;
        let corr = self.name(Opt::correlation);
        let typed = || self.r.arg(Opt::correlation).map(ToString::to_string);
        match self.p.correlation.value()? {
            Some(Value::RowsText(text)) => space.correlate_rows(&corr, &text)?,
            Some(Value::RowsNumbers(v)) => {
                space.correlate(&corr, &typed().unwrap_or_default(), v)?
            }
            _ => {}
        }
        Ok(space)
    }

    /// Refuses a correlation given without the design space whose variables it
    /// correlates.
    pub(crate) fn correlation_without_space(&self) -> Result<(), Error> {
        match self.r.arg(Opt::correlation) {
            Some(c) => Err(self.bad(
                Opt::correlation,
                c,
                format!(
                    "a correlation with a design space ({}) whose continuous variables it \
                     correlates",
                    self.name(Opt::space)
                ),
            )),
            None => Ok(()),
        }
    }

    /// A run in the unit cube of one coordinate per variable, carried into the design
    /// space afterwards by the rule [`cube_rule`] gives (dealt, or a randomised set
    /// through each law's inverse CDF): the options that place points elsewhere or grow
    /// a set are refused.
    pub(super) fn design(&self) -> Result<Resolved, Error> {
        let option = self.name(Opt::space);
        let space = self.design_space()?;
        if let Some(o) = self.first_given(Group::Placement) {
            return Err(self.refuse(
                o,
                format!(
                    "no {} with {option}: a design's variables carry their own ranges and \
                     distributions, and its levels and slices are dealt from one whole \
                     unit-cube set",
                    self.name(o)
                ),
            ));
        }
        if let Some(s) = self.p.s.value()? {
            if s != space.dim() {
                return Err(self.refuse(
                    Opt::s,
                    format!(
                        "the number of variables in {option}, {} (or no {})",
                        space.dim(),
                        self.name(Opt::s)
                    ),
                ));
            }
        }
        let mut inner = self.r.clone();
        inner.space = None;
        inner.correlation = None;
        inner.s = Some(space.dim().into());
        let mut resolved = Ctx::new(&inner, self.spell).resolve()?;
        space.check_n(&option, resolved.job.n())?;
        let rule = cube_rule(&space, &resolved.job);
        resolved.design = Some(space);
        Ok(resolved.with_rule(rule))
    }
}
