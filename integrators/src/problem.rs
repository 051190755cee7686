//! A [`Problem`]: an energy together with the domain its points live in, checked once to
//! agree, so that no integrator can run an energy in a domain it was not made for.

use std::sync::Arc;
use stillpoint_energies::{Domain, Energy, Error, PointSet, Result};

/// An energy and its domain. Build it with [`Problem::new`] (any energy in a given
/// domain, owned), [`Problem::shared`] (shared), [`Problem::borrowed`] (borrowed for the
/// problem's lifetime) or [`Problem::tied`] (an energy that holds its own domain, such
/// as the boundary-aware U_{E,∞,g}).
#[derive(Clone)]
pub struct Problem<'a> {
    energy: Held<'a, dyn Energy + 'a>,
    domain: Held<'a, dyn Domain + 'a>,
}

/// A part of a problem, owned (shared) or borrowed.
enum Held<'a, T: ?Sized> {
    Shared(Arc<T>),
    Borrowed(&'a T),
}

impl<T: ?Sized> Clone for Held<'_, T> {
    fn clone(&self) -> Self {
        match self {
            Held::Shared(a) => Held::Shared(a.clone()),
            Held::Borrowed(r) => Held::Borrowed(r),
        }
    }
}

impl<T: ?Sized> std::ops::Deref for Held<'_, T> {
    type Target = T;
    fn deref(&self) -> &T {
        match self {
            Held::Shared(a) => a,
            Held::Borrowed(r) => r,
        }
    }
}

impl std::fmt::Debug for Problem<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Problem")
            .field("energy", &self.energy.name())
            .field("domain", &&*self.domain)
            .finish()
    }
}

impl<'a> Problem<'a> {
    /// `energy` over `domain`, both owned by the problem:
    /// `Problem::new(Uqp::new(..)?, PeriodicCube::new(s)?)`.
    pub fn new(energy: impl Energy + 'static, domain: impl Domain + 'static) -> Result<Self> {
        Problem::shared(Arc::new(energy), Arc::new(domain))
    }

    /// `energy` over `domain`, shared. An energy that holds its own domain
    /// ([`Energy::domain`]) must be given that domain (the same object, or one equal to
    /// it): an energy measuring distances to one boundary cannot run in another region.
    pub fn shared(energy: Arc<dyn Energy>, domain: Arc<dyn Domain>) -> Result<Self> {
        Problem::checked(Held::Shared(energy), Held::Shared(domain))
    }

    /// `energy` over `domain`, borrowed (for callers that keep both).
    pub fn borrowed(energy: &'a dyn Energy, domain: &'a dyn Domain) -> Result<Self> {
        Problem::checked(Held::Borrowed(energy), Held::Borrowed(domain))
    }

    fn checked(
        energy: Held<'a, dyn Energy + 'a>,
        domain: Held<'a, dyn Domain + 'a>,
    ) -> Result<Self> {
        if let Some(own) = energy.domain() {
            if !same_domain(own.as_ref(), &*domain) {
                return Err(Error::invalid(
                    "domain",
                    format!("{:?}", &*domain),
                    format!(
                        "the domain the energy {} was built for ({own:?})",
                        energy.name()
                    ),
                ));
            }
        }
        if domain.dim() == 0 {
            return Err(Error::invalid("domain dimension", 0, "at least 1"));
        }
        Ok(Problem { energy, domain })
    }

    /// An energy that holds its own domain, run in that domain.
    pub fn tied(energy: Arc<dyn Energy>) -> Result<Problem<'static>> {
        let domain = energy.domain().ok_or_else(|| {
            Error::invalid(
                "energy",
                energy.name(),
                "an energy that holds its own domain (otherwise give the domain)",
            )
        })?;
        Ok(Problem {
            energy: Held::Shared(energy),
            domain: Held::Shared(domain),
        })
    }

    /// The energy.
    pub fn energy(&self) -> &dyn Energy {
        &*self.energy
    }

    /// The domain.
    pub fn domain(&self) -> &dyn Domain {
        &*self.domain
    }

    /// The dimension s of the domain.
    pub fn dim(&self) -> usize {
        self.domain.dim()
    }

    /// Refuses a set whose dimension differs from the domain's or with a point outside
    /// it, naming the first offending point; `what` names the set ("start point").
    pub fn check_inside(&self, what: &str, points: &PointSet) -> Result<()> {
        let domain = self.domain();
        if points.s() != domain.dim() {
            return Err(Error::invalid(
                format!("{what} dimension"),
                points.s(),
                format!("the domain's dimension {}", domain.dim()),
            ));
        }
        if let Some(i) = (0..points.n()).find(|&i| !domain.contains(points.point(i))) {
            return Err(Error::invalid(
                format!("{what} {}", i + 1),
                format!("{:?}", points.point(i)),
                "a point inside the domain",
            ));
        }
        Ok(())
    }
}

/// The same domain: the same object (data pointers compared; the vtables of one type
/// may differ between codegen units, so `Arc::ptr_eq` on trait objects is not reliable),
/// or an equal one — two domains whose complete descriptions agree (their `Debug` text
/// names the type and every parameter; a description that leaves fields out, `..`, is
/// not taken as proof).
fn same_domain(a: &dyn Domain, b: &dyn Domain) -> bool {
    if std::ptr::addr_eq(a as *const dyn Domain, b as *const dyn Domain) {
        return true;
    }
    let (da, db) = (format!("{a:?}"), format!("{b:?}"));
    da == db && !da.contains("..")
}
