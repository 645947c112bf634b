//! The specification, as the model's properties state it: its tables read from
//! `spec/cooperation.md` itself, and its rules (§5, §6.1) written out independently of the
//! library (`rules`), and the messages and answers a state must be written as (`messages`,
//! `responses`), so that the properties say what the spec says rather than what the code does.

use std::collections::BTreeMap;

use cooperation::{Decision, OperatorDecision, Phase, Policy};

pub mod messages;
pub mod responses;
pub mod rules;
pub mod text;

/// The text of the normative specification, compiled in.
pub const SPEC: &str = include_str!("../../../../spec/cooperation.md");

/// The merged-decision table of spec §6.2: (operator, policy, module) → merged.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MergeTable(BTreeMap<(OperatorDecision, Policy, Decision), Decision>);

/// A table row the model could not read.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TableError(pub String);

impl core::fmt::Display for TableError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "spec/cooperation.md: {}", self.0)
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
        let mut table = BTreeMap::new();
        for cells in rows(spec, "| operator | policy | module | merged |")? {
            let line = cells.join(" | ");
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
                "merge table: {} rows do not cover the domain",
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

/// The rows of the table whose header line starts with `header` ([`text::table_rows`]).
fn rows<'a>(spec: &'a str, header: &str) -> Result<Vec<Vec<&'a str>>, TableError> {
    text::table_rows(spec, header).ok_or_else(|| TableError(format!("no table headed {header:?}")))
}

/// The lifecycle table of spec §7: which phase an owner's update may move a scene to.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LifecycleTable(BTreeMap<(Phase, Phase), bool>);

impl LifecycleTable {
    /// Reads the table from the spec text: rows are the current phase, columns the phase asked
    /// for, ✓ allowed and ✗ rejected.
    ///
    /// # Errors
    /// If the table is missing, a cell is neither ✓ nor ✗, or a pair of phases is missing or
    /// repeated.
    pub fn from_spec(spec: &str) -> Result<Self, TableError> {
        let header = "| from \\ to |";
        let columns: Vec<Phase> = spec
            .lines()
            .find(|line| line.starts_with(header))
            .ok_or_else(|| TableError("no lifecycle table".into()))?
            .trim_matches('|')
            .split('|')
            .skip(1)
            .map(|name| word(&Phase::ALL, Phase::as_str, name.trim()))
            .collect::<Result<_, _>>()?;
        let mut table = BTreeMap::new();
        for cells in rows(spec, header)? {
            let Some((from, marks)) = cells.split_first() else {
                continue;
            };
            let from = word(&Phase::ALL, Phase::as_str, from)?;
            if marks.len() != columns.len() {
                return Err(TableError(format!(
                    "lifecycle row {from}: {} cells",
                    marks.len()
                )));
            }
            for (to, mark) in columns.iter().zip(marks) {
                let allowed = match *mark {
                    "✓" => true,
                    "✗" => false,
                    other => return Err(TableError(format!("lifecycle cell {other:?}"))),
                };
                if table.insert((from, *to), allowed).is_some() {
                    return Err(TableError(format!("lifecycle row {from} repeats")));
                }
            }
        }
        if table.len() != Phase::ALL.len() * Phase::ALL.len() {
            return Err(TableError(format!(
                "lifecycle table: {} cells do not cover every pair of phases",
                table.len()
            )));
        }
        Ok(Self(table))
    }

    /// Whether the spec lets an update move a scene from `from` to `to`.
    #[must_use]
    pub fn allows(&self, from: Phase, to: Phase) -> bool {
        self.0.get(&(from, to)).copied().unwrap_or(false)
    }
}

/// Both tables of the spec, read once.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Tables {
    /// Spec §6.2.
    pub merge: MergeTable,
    /// Spec §7.
    pub lifecycle: LifecycleTable,
}

impl Tables {
    /// Reads both tables from the spec text.
    ///
    /// # Errors
    /// As [`MergeTable::from_spec`] and [`LifecycleTable::from_spec`].
    pub fn from_spec(spec: &str) -> Result<Self, TableError> {
        Ok(Self {
            merge: MergeTable::from_spec(spec)?,
            lifecycle: LifecycleTable::from_spec(spec)?,
        })
    }
}
