//! A factor's `detail`: free text from the planning module to the operator, carried as is.

use std::sync::Arc;

/// Free text a planning module gives a factor (AD API `detail`), for example what it is
/// waiting for. No rule reads it; the factors carry it.
///
/// Cloning it never allocates (the text is shared), so a planner that keeps its factor lists
/// from cycle to cycle still allocates nothing once they have grown. The empty text is the
/// default, and holds no allocation.
///
/// ```
/// use cooperation::Detail;
///
/// let detail = Detail::new("waiting for the pedestrian");
/// assert_eq!(detail.as_str(), "waiting for the pedestrian");
/// assert!(Detail::default().is_empty());
/// assert_eq!(Detail::new(""), Detail::default());
/// ```
#[derive(Clone, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Detail(Option<Arc<str>>);

impl Detail {
    /// The empty text.
    pub const EMPTY: Self = Self(None);

    /// The text `text`.
    #[must_use]
    pub fn new(text: &str) -> Self {
        if text.is_empty() {
            Self::EMPTY
        } else {
            Self(Some(Arc::from(text)))
        }
    }

    /// The text.
    #[must_use]
    pub fn as_str(&self) -> &str {
        self.0.as_deref().unwrap_or_default()
    }

    /// Whether the text is empty.
    #[must_use]
    pub const fn is_empty(&self) -> bool {
        self.0.is_none()
    }
}

impl core::fmt::Debug for Detail {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        self.as_str().fmt(f)
    }
}

impl From<&str> for Detail {
    fn from(text: &str) -> Self {
        Self::new(text)
    }
}

#[cfg(feature = "serde")]
impl serde::Serialize for Detail {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_str(self.as_str())
    }
}

#[cfg(feature = "serde")]
impl<'de> serde::Deserialize<'de> for Detail {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let text = String::deserialize(deserializer)?;
        Ok(Self::new(&text))
    }
}
