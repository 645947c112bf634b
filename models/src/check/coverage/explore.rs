//! The search behind [`explore`]: breadth first, level by level, on any number of threads.
//!
//! **Menus and arrivals.** Expanding a state applies every input of the model's `actions` with
//! [`SequentialModel::next_step`] (every successor, stalled or not), and records the state's
//! *menu*: each rule an input fires there, with the identifiers the input names. A pair ending
//! in a state is a rule that led to it (its [`Step::last`]) followed by a menu entry, its scope
//! read by comparing the entry's identifiers with those of the input that led there. So each
//! state also keeps its *arrivals*, the identifier sets of the inputs that reached it, as bits
//! of a `u64`. An arrival met before the state is expanded is paired when it is; one met after,
//! at once, with the stored menu.
//!
//! **Stalled steps.** A stalled step (an input that changed neither the core nor the history)
//! is never expanded: the model offers no action in it. Its successors would be its
//! predecessor's, since a step reads only the core and the history of the step it starts from;
//! so the pairs that start with a stalled step's rule are that rule followed by the
//! predecessor's menu, recorded when the predecessor is expanded.
//!
//! **Symmetry.** With symmetry, one state of each class of states equal up to renaming is kept,
//! its canonical form ([`Step::canonical_step`]), and arrivals and menus are written in its
//! names. An input is *symmetric* when every renaming of it is in the alphabet too; then the menu of a
//! renamed state is the renamed menu, for those inputs. An input that is not (the over-limit
//! batch, naming the first identifier) is also applied to every renaming of the
//! representative, and its menu entries and arrivals are kept per renaming (*slot*). See `docs/verification.md`,
//! *Small scopes*, for why this gives every pair the search without symmetry gives.

use std::collections::hash_map::Entry as Slot;
use std::collections::HashMap;
use std::hash::BuildHasher;
use std::sync::atomic::Ordering::Relaxed;
use std::sync::{Arc, Mutex, MutexGuard, PoisonError};
use std::time::Instant;

use cooperation::Rule;
use stateright::Model;

use super::progress::{CoverageError, Found, Progress, MAX_COVERED_SCENES};
use super::{named, renamed_input, Pairs, Scope, RULES};
use crate::check::budget::Halt;
use crate::model::sequential::{identity, inverse, Names, SequentialModel, Step};

/// States a worker takes from the level at a time.
const CHUNK: usize = 256;

/// Shards of the table of states seen.
const SHARDS: usize = 64;

/// A menu not yet known: the state is waiting to be expanded.
const UNEXPANDED: u32 = u32::MAX;

/// What the table keeps of a state: its arrivals by symmetric inputs (bit `m` for the
/// identifier set `m`) and by the others (bit `slot · 2^scenes + m`), and its menu's number.
#[derive(Clone, Copy)]
struct Seen {
    symmetric: u64,
    other: u64,
    menu: u32,
}

type Table = HashMap<u64, Seen, foldhash::fast::FixedState>;

/// The distinct menus, numbered.
#[derive(Default)]
struct Menus {
    numbers: HashMap<Arc<[u64]>, u32, foldhash::fast::FixedState>,
    menus: Vec<Arc<[u64]>>,
}

fn lock<T>(mutex: &Mutex<T>) -> MutexGuard<'_, T> {
    mutex.lock().unwrap_or_else(PoisonError::into_inner)
}

/// The bit for position `at` in a `u64` (none past 63).
fn bit(at: u64) -> u64 {
    u32::try_from(at)
        .ok()
        .and_then(|shift| 1_u64.checked_shl(shift))
        .unwrap_or(0)
}

/// Every set bit's position.
fn bits(words: &[u64]) -> impl Iterator<Item = usize> + '_ {
    words.iter().enumerate().flat_map(|(at, word)| {
        (0..64_usize)
            .filter(move |b| word & (1 << b) != 0)
            .map(move |b| at * 64 + b)
    })
}

fn set(words: &mut [u64], at: usize) {
    if let Some(word) = words.get_mut(at / 64) {
        *word |= 1 << (at % 64);
    }
}

/// An identifier set renamed by `names`.
fn rename_set(names: &Names, ids: u64) -> u64 {
    bits(&[ids])
        .filter_map(|old| names.get(old))
        .fold(0, |renamed, new| renamed | bit(*new as u64))
}

/// Every permutation of the first `n` identifiers (the others keep their names), the identity
/// first.
fn permutations(n: usize) -> Vec<Names> {
    let mut all = vec![identity()];
    for position in 1..n {
        let mut more = Vec::new();
        for names in &all {
            for with in 0..position {
                let mut swapped = *names;
                swapped.swap(position, with);
                more.push(swapped);
            }
        }
        all.extend(more);
    }
    all
}

/// A worker's tallies, added to the [`Progress`] after every chunk.
#[derive(Default)]
struct Tally {
    pairs: Pairs,
    states: usize,
    concrete: usize,
    arrivals: usize,
    transitions: u64,
    renamed: u64,
}

/// What every worker shares.
struct Search<'a> {
    model: &'a SequentialModel,
    /// Identifier sets: `2^scenes`.
    sets: usize,
    /// The renamings tried (only the identity without symmetry), and their inverses.
    renamings: Vec<Names>,
    inverses: Vec<Names>,
    /// Per action: the identifiers its input names, and whether the input is symmetric.
    named: Vec<u64>,
    symmetric: Vec<bool>,
    seen: Vec<Mutex<Table>>,
    menus: Mutex<Menus>,
    progress: &'a Progress,
    halt: &'a Halt,
}

impl Search<'_> {
    fn symmetry(&self) -> bool {
        self.renamings.len() > 1
    }

    /// Words per menu slot: a bit per rule and identifier set.
    const fn width(&self) -> usize {
        (RULES * self.sets).div_ceil(64)
    }

    fn fingerprint(step: &Step) -> u64 {
        foldhash::quality::FixedState::with_seed(0x7061_6972).hash_one(step)
    }

    fn shard(&self, key: u64) -> Result<MutexGuard<'_, Table>, CoverageError> {
        let at = usize::try_from(key >> 58).unwrap_or(0) % SHARDS;
        self.seen.get(at).map(lock).ok_or(CoverageError::Internal)
    }

    /// Records `first` followed by every entry of the union of `parts` (menu slots), the first
    /// input having named `first_set`.
    fn pair(&self, tally: &mut Tally, first: Rule, first_set: u64, parts: &[&[u64]]) {
        for at in 0..self.width() {
            let word = parts
                .iter()
                .fold(0, |word, part| word | part.get(at).copied().unwrap_or(0));
            for entry in bits(&[word]).map(|b| at * 64 + b) {
                if let Some(then) = Rule::ALL.get(entry / self.sets) {
                    let then_set = (entry % self.sets) as u64;
                    tally
                        .pairs
                        .insert(first, *then, Scope::of(first_set, then_set));
                }
            }
        }
    }

    /// Pairs `first` (fired by an input naming `first_set`) with a menu: with every slot for an
    /// arrival by a symmetric input (`renaming` `None`), with the symmetric inputs' slot and
    /// renaming `r`'s for the others.
    fn pair_menu(
        &self,
        tally: &mut Tally,
        (first, first_set): (Rule, u64),
        menu: &[u64],
        renaming: Option<usize>,
    ) {
        let slots: Vec<&[u64]> = menu.chunks(self.width().max(1)).collect();
        match renaming {
            None => self.pair(tally, first, first_set, &slots),
            Some(r) => {
                let parts: Vec<&[u64]> = [0, 1 + r]
                    .iter()
                    .filter_map(|at| slots.get(*at).copied())
                    .collect();
                self.pair(tally, first, first_set, &parts);
            }
        }
    }

    fn number(&self, menu: Vec<u64>) -> Result<(u32, Arc<[u64]>), CoverageError> {
        let menu: Arc<[u64]> = menu.into();
        let mut menus = lock(&self.menus);
        if let Some(number) = menus.numbers.get(&menu) {
            return Ok((*number, menu));
        }
        let number = u32::try_from(menus.menus.len())
            .ok()
            .filter(|n| *n != UNEXPANDED)
            .ok_or(CoverageError::Menus)?;
        menus.menus.push(Arc::clone(&menu));
        menus.numbers.insert(Arc::clone(&menu), number);
        Ok((number, menu))
    }

    fn menu(&self, number: u32) -> Option<Arc<[u64]>> {
        lock(&self.menus).menus.get(number as usize).cloned()
    }
}

impl Search<'_> {
    /// Expands one state kept: its menu (every input, and the inputs that are not symmetric in
    /// every other renaming of it), the pairs ending in it and those starting with a stalled
    /// step after it; the states it reaches first go to `next`.
    fn expand(
        &self,
        (key, step): &(u64, Step),
        tally: &mut Tally,
        next: &mut Vec<(u64, Step)>,
    ) -> Result<(), CoverageError> {
        let width = self.width();
        let slots = 1 + self.renamings.len();
        let mut menu = vec![0; slots * width];
        let mut stalled = vec![0; slots * width];
        let mut actions = Vec::new();
        self.model.actions(step, &mut actions);
        for action in actions {
            let ids = self.named.get(action).copied().unwrap_or(0);
            let symmetric = self.symmetric.get(action).copied().unwrap_or(true);
            let Some(after) = self.model.next_step(step, action) else {
                continue;
            };
            tally.transitions += 1;
            let Some(rule) = after.last else {
                continue;
            };
            let at =
                (usize::from(!symmetric)) * width * 64 + rule as usize * self.sets + ids as usize;
            set(&mut menu, at);
            if after.stalled {
                set(&mut stalled, at);
            } else {
                self.arrive(after, ids, !symmetric, tally, next)?;
            }
        }
        let mut orbit = vec![*key];
        for (r, names) in self.renamings.iter().enumerate().skip(1) {
            let member = step.renamed(names).ok_or(CoverageError::Internal)?;
            let fingerprint = Self::fingerprint(&member);
            if !orbit.contains(&fingerprint) {
                orbit.push(fingerprint);
            }
            let back = self.inverses.get(r).ok_or(CoverageError::Internal)?;
            let mut actions = Vec::new();
            self.model.actions(&member, &mut actions);
            for action in actions {
                if self.symmetric.get(action).copied().unwrap_or(true) {
                    continue;
                }
                let ids = self.named.get(action).copied().unwrap_or(0);
                let Some(after) = self.model.next_step(&member, action) else {
                    continue;
                };
                tally.renamed += 1;
                let Some(rule) = after.last else {
                    continue;
                };
                let at = (1 + r) * width * 64
                    + rule as usize * self.sets
                    + rename_set(back, ids) as usize;
                set(&mut menu, at);
                if after.stalled {
                    set(&mut stalled, at);
                } else {
                    self.arrive(after, ids, true, tally, next)?;
                }
            }
        }
        tally.concrete += orbit.len();
        let (number, menu) = self.number(menu)?;
        let (symmetric, other) = {
            let mut table = self.shard(*key)?;
            let seen = table.get_mut(key).ok_or(CoverageError::Internal)?;
            seen.menu = number;
            (seen.symmetric, seen.other)
        };
        if let Some(first) = step.last {
            for ids in bits(&[symmetric]) {
                self.pair_menu(tally, (first, ids as u64), &menu, None);
            }
            for at in bits(&[other]) {
                let (r, ids) = (at / self.sets, (at % self.sets) as u64);
                self.pair_menu(tally, (first, ids), &menu, Some(r));
            }
        }
        for at in bits(&stalled) {
            let (slot, entry) = (at / (width * 64), at % (width * 64));
            let Some(first) = Rule::ALL.get(entry / self.sets) else {
                continue;
            };
            let ids = (entry % self.sets) as u64;
            let renaming = slot.checked_sub(1);
            self.pair_menu(tally, (*first, ids), &menu, renaming);
        }
        Ok(())
    }

    /// `after` reached by an input naming `ids` (symmetric or not): a new state goes to `next`;
    /// a new arrival at a state already expanded is paired with its menu at once.
    fn arrive(
        &self,
        after: Step,
        ids: u64,
        other: bool,
        tally: &mut Tally,
        next: &mut Vec<(u64, Step)>,
    ) -> Result<(), CoverageError> {
        let (state, names) = if self.symmetry() {
            let names = after.representative_names();
            (after.canonical_step(), names)
        } else {
            (after, identity())
        };
        let ids = rename_set(&names, ids);
        // The renaming under which `after` is its representative's: the inverse of `names`.
        let renaming = if other {
            let back = inverse(&names);
            let r = self
                .renamings
                .iter()
                .position(|names| *names == back)
                .ok_or(CoverageError::Internal)?;
            Some(r)
        } else {
            None
        };
        let flag = match renaming {
            None => bit(ids),
            Some(r) => bit((r * self.sets) as u64 + ids),
        };
        let key = Self::fingerprint(&state);
        let expanded = {
            let mut table = self.shard(key)?;
            match table.entry(key) {
                Slot::Vacant(slot) => {
                    let (symmetric, other) = if other { (0, flag) } else { (flag, 0) };
                    slot.insert(Seen {
                        symmetric,
                        other,
                        menu: UNEXPANDED,
                    });
                    None
                }
                Slot::Occupied(mut slot) => {
                    let seen = slot.get_mut();
                    let arrivals = if other {
                        &mut seen.other
                    } else {
                        &mut seen.symmetric
                    };
                    if *arrivals & flag != 0 {
                        return Ok(());
                    }
                    *arrivals |= flag;
                    Some(seen.menu)
                }
            }
        };
        tally.arrivals += 1;
        match expanded {
            None => {
                tally.states += 1;
                next.push((key, state));
            }
            Some(UNEXPANDED) => {}
            Some(number) => {
                if let (Some(menu), Some(first)) = (self.menu(number), state.last) {
                    self.pair_menu(tally, (first, ids), &menu, renaming);
                }
            }
        }
        Ok(())
    }

    fn flush(&self, tally: &mut Tally) {
        let progress = self.progress;
        progress.record(&tally.pairs);
        progress.states.fetch_add(tally.states, Relaxed);
        progress.concrete.fetch_add(tally.concrete, Relaxed);
        progress.arrivals.fetch_add(tally.arrivals, Relaxed);
        progress.transitions.fetch_add(tally.transitions, Relaxed);
        progress.renamed.fetch_add(tally.renamed, Relaxed);
        *tally = Tally {
            pairs: tally.pairs,
            ..Tally::default()
        };
    }

    /// One worker's share of a level: chunks of it until none is left, each dropped once
    /// expanded.
    fn work(
        &self,
        chunks: &Mutex<Vec<Vec<(u64, Step)>>>,
    ) -> Result<Vec<(u64, Step)>, CoverageError> {
        let mut next = Vec::new();
        let mut tally = Tally::default();
        while !self.halt.is_set() {
            let Some(chunk) = lock(chunks).pop() else {
                break;
            };
            for state in &chunk {
                self.expand(state, &mut tally, &mut next)?;
            }
            self.flush(&mut tally);
        }
        self.flush(&mut tally);
        Ok(next)
    }

    /// Expands a level on `threads` threads; the states it reaches first, the next level.
    fn level(
        &self,
        level: Vec<(u64, Step)>,
        threads: usize,
    ) -> Result<Vec<(u64, Step)>, CoverageError> {
        let mut chunks = Vec::new();
        let mut states = level.into_iter();
        loop {
            let chunk: Vec<_> = states.by_ref().take(CHUNK).collect();
            if chunk.is_empty() {
                break;
            }
            chunks.push(chunk);
        }
        let chunks = Mutex::new(chunks);
        std::thread::scope(|scope| {
            let workers: Vec<_> = (0..threads.max(1))
                .map(|_| scope.spawn(|| self.work(&chunks)))
                .collect();
            let mut next = Vec::new();
            let mut failed = None;
            for worker in workers {
                match worker.join() {
                    Ok(Ok(mut part)) => next.append(&mut part),
                    Ok(Err(error)) => failed = Some(error),
                    Err(_) => failed = Some(CoverageError::Worker),
                }
            }
            failed.map_or(Ok(next), Err)
        })
    }
}

/// Measures every pair of consecutive rules over the reachable states of `model`, breadth
/// first on `threads` threads, keeping one state per class of states equal up to renaming when
/// `symmetry` is set (sound only where the model's check uses symmetry: every retired
/// identifier remembered). Counts and pairs go to `progress` as they are found; `halt` stops
/// the run, which then returns what it found, marked incomplete.
///
/// # Errors
/// If the model has more identifiers than [`MAX_COVERED_SCENES`] allows, its initial state
/// cannot be built, or a worker thread fails (what was found until then is in `progress`).
pub fn explore(
    model: &SequentialModel,
    symmetry: bool,
    threads: usize,
    progress: &Progress,
    halt: &Halt,
) -> Result<Found, CoverageError> {
    let started = Instant::now();
    let scenes = model.bounds().scenes;
    let (plain, symmetric) = MAX_COVERED_SCENES;
    if scenes > if symmetry { symmetric } else { plain } {
        return Err(CoverageError::Scenes(scenes));
    }
    let renamings = if symmetry {
        permutations(scenes)
    } else {
        vec![identity()]
    };
    let alphabet = model.alphabet();
    let search = Search {
        model,
        sets: 1 << scenes,
        inverses: renamings.iter().map(inverse).collect(),
        named: alphabet.iter().map(named).collect(),
        symmetric: alphabet
            .iter()
            .map(|input| {
                renamings
                    .iter()
                    .all(|names| alphabet.contains(&renamed_input(input, names)))
            })
            .collect(),
        renamings,
        seen: (0..SHARDS).map(|_| Mutex::default()).collect(),
        menus: Mutex::default(),
        progress,
        halt,
    };
    let initial = model
        .initial()
        .map_err(|e| CoverageError::Initial(e.to_string()))?;
    let initial = if symmetry {
        initial.canonical_step()
    } else {
        initial
    };
    let key = Search::fingerprint(&initial);
    search.shard(key)?.insert(
        key,
        Seen {
            symmetric: 0,
            other: 0,
            menu: UNEXPANDED,
        },
    );
    progress.states.fetch_add(1, Relaxed);
    let mut level = vec![(key, initial)];
    while !level.is_empty() && !halt.is_set() {
        progress.frontier.store(level.len(), Relaxed);
        level = search.level(level, threads)?;
        if !halt.is_set() {
            progress.levels.fetch_add(1, Relaxed);
        }
    }
    // A halted level leaves states unexpanded, and perhaps none in the next level.
    let complete = level.is_empty() && !halt.is_set();
    progress.frontier.store(level.len(), Relaxed);
    Ok(progress.found(complete, started.elapsed()))
}
