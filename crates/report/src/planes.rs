//! Diagrams on other axes that sweeps ask the report for (`[report] planes` in a sweep file):
//! beta against R0 at fixed alpha~/L~, E0 against beta, ... Each plane is drawn once, however
//! many sweeps ask, from every diagram the report shows (so a sweep over R0 = 32 is drawn
//! beside the paper's R0 = 40 where their alpha~/L~ agree), keeping the diagrams of the plane
//! that hold a point of a sweep that asked.

use cellsweep_plot::phase::Diagram;
use cellsweep_stats::Plane;

use crate::collection::Collection;
use crate::figures::plane_diagrams;
use crate::Results;

/// Why an asked plane cannot be drawn.
#[derive(Debug, Clone, thiserror::Error)]
pub enum PlaneDrawError {
    /// The shown diagrams do not merge into one set (e.g. different classifiers).
    #[error(transparent)]
    Merge(std::sync::Arc<crate::load::LoadError>),
    #[error(transparent)]
    Plane(#[from] cellsweep_stats::PlaneError),
}

/// One plane asked for, and what could be drawn of it.
#[derive(Debug, Clone)]
pub struct AskedPlane {
    pub plane: Plane,
    /// The sweeps that asked for it.
    pub asked_by: Vec<String>,
    /// Its diagrams (each with the stem of its file name), or why it cannot be drawn.
    pub drawn: Result<Vec<(String, Diagram)>, PlaneDrawError>,
}

impl AskedPlane {
    /// "β against R0, one diagram per xt and sigma".
    pub fn title(&self) -> String {
        let by = match &self.plane.by {
            Some(by) if by.is_empty() => ", every point in one diagram".to_string(),
            Some(by) => format!(", one diagram per {}", by.join(" and ")),
            None => String::new(),
        };
        format!("{} against {}{by}", self.plane.y, self.plane.x)
    }
}

/// Every plane the shown diagrams' sweeps ask for, in the order first asked.
pub fn asked_planes(collection: &Collection<'_>) -> Vec<AskedPlane> {
    let mut asked: Vec<AskedPlane> = Vec::new();
    for s in &collection.diagrams {
        let Some(p) = &s.results.provenance else {
            continue;
        };
        for plane in &p.planes {
            let name = s.results.name.clone();
            match asked.iter_mut().find(|a| a.plane == *plane) {
                Some(a) if !a.asked_by.contains(&name) => a.asked_by.push(name),
                Some(_) => {}
                None => asked.push(AskedPlane {
                    plane: plane.clone(),
                    asked_by: vec![name],
                    drawn: Ok(Vec::new()),
                }),
            }
        }
    }
    for a in &mut asked {
        a.drawn = draw(collection, a);
    }
    asked
}

/// The plane's diagrams from every shown diagram, those holding a point of an asking sweep.
fn draw(
    collection: &Collection<'_>,
    a: &AskedPlane,
) -> Result<Vec<(String, Diagram)>, PlaneDrawError> {
    let mut asking: Vec<bool> = Vec::new();
    let mut sets = Vec::new();
    for s in &collection.diagrams {
        let part = s.results.clone().only(|c| s.key.holds(c));
        asking.extend(std::iter::repeat_n(
            a.asked_by.contains(&s.results.name),
            part.counts.len(),
        ));
        sets.push(part);
    }
    let mut all =
        Results::merged(sets).map_err(|e| PlaneDrawError::Merge(std::sync::Arc::new(e)))?;
    all.name = "shown".into();
    let groups = a.plane.groups(&all.counts, &all.scales)?;
    let mut keep = vec![false; all.counts.len()];
    for g in groups
        .iter()
        .filter(|g| g.points.iter().any(|&i| asking[i]))
    {
        for &i in &g.points {
            keep[i] = true;
        }
    }
    let kept = all.keep(&keep);
    let mut drawn = plane_diagrams(&kept, &a.plane)?;
    for (_, d) in &mut drawn {
        // "shown: xt = 49.95, sigma = 5" -> "xt = 49.95, sigma = 5"
        if let Some(t) = d.title.strip_prefix("shown: ") {
            d.title = t.to_string();
        }
        if d.title.is_empty() || d.title == "shown:" {
            d.title = "every point".to_string();
        }
    }
    Ok(drawn)
}
