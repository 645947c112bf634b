//! The specification's merged-decision table, read from `spec/cooperation.md` itself, so the
//! model's properties state what the spec says rather than what the code does.

use std::collections::BTreeMap;

use cooperation::{Decision, OperatorDecision, Policy};

/// The text of the normative specification, compiled in.
pub const SPEC: &str = include_str!("../../spec/cooperation.md");

/// The merged-decision table of spec §6.2: (operator, policy, module) → merged.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MergeTable(BTreeMap<(OperatorDecision, Policy, Decision), Decision>);

/// A table row the model could not read.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TableError(pub String);

impl core::fmt::Display for TableError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "spec/cooperation.md merge table: {}", self.0)
    }
}

impl std::error::Error for TableError {}

fn word<T: Copy>(all: &[T], name: fn(T) -> &'static str, text: &str) -> Result<T, TableError> {
    all.iter()
        .copied()
        .find(|value| name(*value) == text)
        .ok_or_else(|| TableError(format!("unknown value {text:?}")))
}

impl MergeTable {
    /// Reads the table from the spec text.
    ///
    /// # Errors
    /// If the table is missing, a row is malformed or repeated, or the domain is not covered.
    pub fn from_spec(spec: &str) -> Result<Self, TableError> {
        let mut lines = spec
            .lines()
            .skip_while(|line| !line.starts_with("| operator | policy | module | merged |"));
        if lines.next().is_none() {
            return Err(TableError("no table".into()));
        }
        let mut table = BTreeMap::new();
        for line in lines.skip(1).take_while(|line| line.starts_with('|')) {
            let cells: Vec<&str> = line.trim_matches('|').split('|').map(str::trim).collect();
            let [operator, policy, module, merged] = cells.as_slice() else {
                return Err(TableError(format!("row {line:?} does not have 4 cells")));
            };
            let key = (
                word(&OperatorDecision::ALL, OperatorDecision::as_str, operator)?,
                word(&Policy::ALL, Policy::as_str, policy)?,
                word(&Decision::ALL, Decision::as_str, module)?,
            );
            let merged = word(&Decision::ALL, Decision::as_str, merged)?;
            if table.insert(key, merged).is_some() {
                return Err(TableError(format!("row {line:?} repeats")));
            }
        }
        if table.len() != OperatorDecision::ALL.len() * Policy::ALL.len() * Decision::ALL.len() {
            return Err(TableError(format!(
                "{} rows do not cover the domain",
                table.len()
            )));
        }
        Ok(Self(table))
    }

    /// The merged decision the spec's table gives.
    #[must_use]
    pub fn merged(
        &self,
        operator: OperatorDecision,
        policy: Policy,
        module: Decision,
    ) -> Option<Decision> {
        self.0.get(&(operator, policy, module)).copied()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_the_specs_table() {
        let table = MergeTable::from_spec(SPEC).expect("the spec's table reads");
        assert_eq!(
            table.merged(
                OperatorDecision::Undecided,
                Policy::Required,
                Decision::Activate
            ),
            Some(Decision::Deactivate)
        );
        assert!(MergeTable::from_spec("no table here").is_err());
    }
}
