//! The credentials in force, each with its places and what tells its connections that it was
//! revoked; replaced whole when the credentials are reloaded ([`crate::serve_reloading`]).
//!
//! A reload keeps each credential that is unchanged (same role, name, token and interfaces)
//! with its places and its open connections. Every other credential of the old set is revoked:
//! its connections are closed and its token is refused from then on. A credential new to the
//! set gets places of its own.

use std::sync::{Arc, PoisonError, RwLock};

use tokio::sync::{watch, Semaphore};

use crate::auth::{Credential, Credentials};

/// One credential's places and revocation.
#[derive(Debug)]
pub(crate) struct Entry {
    /// Its connections' places.
    pub(crate) places: Arc<Semaphore>,
    /// Set when it is revoked.
    revoked: watch::Sender<bool>,
}

impl Entry {
    fn new(places: usize) -> Arc<Self> {
        Arc::new(Self {
            places: Arc::new(Semaphore::new(places)),
            revoked: watch::channel(false).0,
        })
    }

    /// Completes when the credential is revoked.
    pub(crate) fn revoked(&self) -> impl std::future::Future<Output = ()> + Send + 'static {
        let mut told = self.revoked.subscribe();
        async move {
            if told.wait_for(|revoked| *revoked).await.is_err() {
                // Never revoked, and never will be: its entry is gone only with the node.
                std::future::pending::<()>().await;
            }
        }
    }
}

/// The credentials in force, and each one's entry, in the same order.
#[derive(Debug)]
pub(crate) struct Set {
    pub(crate) credentials: Credentials,
    pub(crate) entries: Vec<Arc<Entry>>,
}

/// What a reload changed.
#[derive(Clone, PartialEq, Eq, Debug, Default)]
pub struct Reloaded {
    /// The credentials kept, with their connections.
    pub kept: Vec<String>,
    /// Those revoked: their connections closed, their tokens refused.
    pub revoked: Vec<String>,
    /// Those added.
    pub added: Vec<String>,
}

/// The credentials in force.
#[derive(Debug)]
pub(crate) struct Keyring {
    set: RwLock<Arc<Set>>,
}

impl Keyring {
    pub(crate) fn new(credentials: Credentials) -> Self {
        let entries = credentials
            .list()
            .iter()
            .map(|_| Entry::new(credentials.places))
            .collect();
        Self {
            set: RwLock::new(Arc::new(Set {
                credentials,
                entries,
            })),
        }
    }

    /// The set in force now.
    pub(crate) fn current(&self) -> Arc<Set> {
        Arc::clone(&self.set.read().unwrap_or_else(PoisonError::into_inner))
    }

    /// Puts `credentials` in force: unchanged credentials are kept with their places and
    /// connections, the others revoked.
    pub(crate) fn reload(&self, credentials: Credentials) -> Reloaded {
        let mut set = self.set.write().unwrap_or_else(PoisonError::into_inner);
        let same = |old: &Credential, new: &Credential| old == new;
        let mut reloaded = Reloaded::default();
        let entries = credentials
            .list()
            .iter()
            .map(|new| {
                let kept = (set.credentials.places == credentials.places)
                    .then(|| {
                        set.credentials
                            .list()
                            .iter()
                            .zip(&set.entries)
                            .find(|(old, _)| same(old, new))
                    })
                    .flatten();
                match kept {
                    Some((_, entry)) => {
                        reloaded.kept.push(new.name.clone());
                        Arc::clone(entry)
                    }
                    None => {
                        reloaded.added.push(new.name.clone());
                        Entry::new(credentials.places)
                    }
                }
            })
            .collect::<Vec<_>>();
        for (old, entry) in set.credentials.list().iter().zip(&set.entries) {
            if !entries.iter().any(|kept| Arc::ptr_eq(kept, entry)) {
                reloaded.revoked.push(old.name.clone());
                entry.revoked.send_replace(true);
            }
        }
        *set = Arc::new(Set {
            credentials,
            entries,
        });
        reloaded
    }
}
