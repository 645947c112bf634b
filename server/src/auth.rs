//! Who a client is: the credentials the node accepts, and what each lets a connection do.
//!
//! A client presents a credential when it opens its WebSocket, as a bearer token: in the
//! upgrade request's `Authorization: Bearer TOKEN` header (`roslibpy`'s `headers=`, any client
//! that is not a browser) or as the URL's `token` query parameter (`ws://HOST:PORT/?token=TOKEN`:
//! a browser cannot set headers on a WebSocket; the operator panel asks for the token and puts
//! it there). It is checked before the WebSocket exists, so a client without a credential
//! never holds a connection's place, and each credential has places of its own that no other
//! client can take ([`Credentials::places`]).
//!
//! Each credential has a role:
//! - **operator**: the AD API services (`set_commands`, `set_policies`, `get_policies`), the
//!   factor topics and `rosapi`;
//! - **module**: `/cooperation/rtc/sync` for the RTC interfaces it is bound to, and the same
//!   reads (`get_policies`, the topics, `rosapi`).
//!
//! A node started without credentials lets every client do everything ([`Grant::Anyone`]);
//! it refuses to start on an address other than loopback unless told to (`--anonymous`).
//!
//! The credentials file has one credential a line: the role, a name for the logs, the token,
//! and for a module the interfaces it may report for. `#` starts a comment.
//!
//! ```text
//! operator  panel   9hX2c4mQwZr7Lk0TtB5yNvE1aPu8sDfG
//! module    lanes   Qm4v8ZpLx1Ck7RtY2wHs9NbE3uJd6FgA  lane_change_left lane_change_right
//! ```

use std::collections::BTreeSet;
use std::fmt;

use axum::http::{header, HeaderMap, Uri};

/// The fewest characters a token may have.
pub const MIN_TOKEN: usize = 24;

/// The fewest different characters a token may have: a random token of 24 characters has
/// about 20, and one with fewer than this (`aaaa…`, `abab…`) was not made at random.
pub const MIN_DISTINCT: usize = 8;

/// The tokens the documentation shows (docs/server.md, and this module's): anyone can read
/// them, so a file that uses them is refused.
pub const EXAMPLE_TOKENS: [&str; 2] = [
    "9hX2c4mQwZr7Lk0TtB5yNvE1aPu8sDfG",
    "Qm4v8ZpLx1Ck7RtY2wHs9NbE3uJd6FgA",
];

/// How to make a token, for the messages that refuse one.
const MAKE_ONE: &str = "make one at random, for example with `openssl rand -hex 24`";

/// A credential's role.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Role {
    /// Commands scenes and sets policies.
    Operator,
    /// Reports scenes through its RTC interfaces.
    Module,
}

/// One credential: who, which role, and for a module, which interfaces.
#[derive(Clone, PartialEq, Eq)]
pub struct Credential {
    /// Its name in the logs (the token is never logged).
    pub name: String,
    /// Its role.
    pub role: Role,
    token: String,
    /// The RTC interfaces a module may report for; empty for an operator.
    pub interfaces: BTreeSet<String>,
}

impl fmt::Debug for Credential {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Credential")
            .field("name", &self.name)
            .field("role", &self.role)
            .field("interfaces", &self.interfaces)
            .finish_non_exhaustive()
    }
}

/// The credentials a node accepts.
#[derive(Clone, PartialEq, Eq, Debug, Default)]
pub struct Credentials {
    list: Vec<Credential>,
    /// Connections each credential may have open at once.
    pub places: usize,
}

/// Why a credentials file does not read: its line (from 1) and the reason.
#[derive(Clone, PartialEq, Eq, Debug)]
pub struct CredentialsError {
    /// The line.
    pub line: usize,
    /// What is wrong with it.
    pub reason: String,
}

impl fmt::Display for CredentialsError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "line {}: {}", self.line, self.reason)
    }
}

impl std::error::Error for CredentialsError {}

/// Whether a token has only the characters a URL carries unescaped.
fn token_characters(token: &str) -> bool {
    token
        .bytes()
        .all(|b| b.is_ascii_alphanumeric() || matches!(b, b'-' | b'.' | b'_' | b'~'))
}

/// The text of the credentials file at `path`, if only its owner may read or change it.
///
/// # Errors
/// The file cannot be read; or (on Unix) its mode lets its group or anyone else read or write
/// it: its tokens let whoever reads them act as the operator or a module.
pub fn read_file(path: &std::path::Path) -> Result<String, String> {
    let at = path.display();
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let mode = std::fs::metadata(path)
            .map_err(|error| format!("{at}: {error}"))?
            .permissions()
            .mode();
        if mode & 0o077 != 0 {
            return Err(format!(
                "{at}: its mode is {:o}, so others than its owner may read or change its tokens; \
                 give it mode 600 (`chmod 600 {at}`)",
                mode & 0o777
            ));
        }
    }
    std::fs::read_to_string(path).map_err(|error| format!("{at}: {error}"))
}

impl Credentials {
    /// Reads a credentials file; `interfaces` are the RTC interfaces the node has.
    ///
    /// # Errors
    /// The first line that is not a credential: an unknown role, a missing name or token, a
    /// token shorter than [`MIN_TOKEN`], with characters other than letters, digits and
    /// `-._~`, with fewer than [`MIN_DISTINCT`] different characters or one of the
    /// documentation's [`EXAMPLE_TOKENS`], a name or token used twice, a module without interfaces or with one the node
    /// does not have, an operator with interfaces. A file with no credential is an error too.
    pub fn parse(text: &str, interfaces: &[&str], places: usize) -> Result<Self, CredentialsError> {
        let mut list: Vec<Credential> = Vec::new();
        for (index, line) in text.lines().enumerate() {
            let line_number = index + 1;
            let fail = |reason: String| CredentialsError {
                line: line_number,
                reason,
            };
            let content = line.split('#').next().unwrap_or_default();
            let mut words = content.split_whitespace();
            let Some(role) = words.next() else { continue };
            let role = match role {
                "operator" => Role::Operator,
                "module" => Role::Module,
                other => {
                    return Err(fail(format!(
                        "{other:?} is not a role: give operator or module"
                    )))
                }
            };
            let (Some(name), Some(token)) = (words.next(), words.next()) else {
                return Err(fail(
                    "a credential is a role, a name and a token".to_owned(),
                ));
            };
            if token.len() < MIN_TOKEN || !token_characters(token) {
                return Err(fail(format!(
                    "the token of {name:?} must have at least {MIN_TOKEN} characters, each a \
                     letter, a digit or one of -._~"
                )));
            }
            let distinct = token.bytes().collect::<BTreeSet<u8>>().len();
            if distinct < MIN_DISTINCT {
                return Err(fail(format!(
                    "the token of {name:?} has {distinct} different characters, fewer than \
                     {MIN_DISTINCT}: it is not random; {MAKE_ONE}"
                )));
            }
            if EXAMPLE_TOKENS.contains(&token) {
                return Err(fail(format!(
                    "the token of {name:?} is an example from the documentation, which anyone \
                     can read; {MAKE_ONE}"
                )));
            }
            if list.iter().any(|c| c.name == name) {
                return Err(fail(format!("the name {name:?} is used twice")));
            }
            if list.iter().any(|c| c.token == token) {
                return Err(fail(format!("the token of {name:?} is used twice")));
            }
            let bound: BTreeSet<String> = words.map(str::to_owned).collect();
            if let Some(unknown) = bound.iter().find(|i| !interfaces.contains(&i.as_str())) {
                return Err(fail(format!(
                    "{unknown:?} is not an RTC interface of this node ({})",
                    interfaces.join(", ")
                )));
            }
            match (role, bound.is_empty()) {
                (Role::Module, true) => {
                    return Err(fail(format!(
                        "module {name:?} names no RTC interface it may report for"
                    )))
                }
                (Role::Operator, false) => {
                    return Err(fail(format!(
                        "operator {name:?} names RTC interfaces: only a module reports for them"
                    )))
                }
                _ => {}
            }
            list.push(Credential {
                name: name.to_owned(),
                role,
                token: token.to_owned(),
                interfaces: bound,
            });
        }
        if list.is_empty() {
            return Err(CredentialsError {
                line: text.lines().count(),
                reason: "no credential in the file".to_owned(),
            });
        }
        Ok(Self { list, places })
    }

    /// The credentials, in the file's order.
    #[must_use]
    pub fn list(&self) -> &[Credential] {
        &self.list
    }

    /// The index of the credential whose token a request presents.
    ///
    /// # Errors
    /// Why the request is not let in: it presents no token, or one that is no credential's.
    pub fn identify(&self, headers: &HeaderMap, uri: &Uri) -> Result<usize, Unidentified> {
        let token = presented(headers, uri).ok_or(Unidentified::NonePresented)?;
        // Every credential is compared, each in time independent of where they differ.
        let mut found = None;
        for (index, credential) in self.list.iter().enumerate() {
            if same(credential.token.as_bytes(), token.as_bytes()) {
                found = Some(index);
            }
        }
        found.ok_or(Unidentified::Unknown)
    }
}

/// Why a request is not let in with a credential.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Unidentified {
    /// It presents no token.
    NonePresented,
    /// It presents a token that is no credential's: a guess ([`crate::guesses`]).
    Unknown,
}

impl Unidentified {
    /// The reason, as the refusal says it.
    #[must_use]
    pub const fn as_str(self) -> &'static str {
        match self {
            Self::NonePresented => "no credential presented",
            Self::Unknown => "a credential the node does not have",
        }
    }
}

/// The token a request presents: its `Authorization: Bearer` header, else its URL's `token`.
fn presented<'a>(headers: &'a HeaderMap, uri: &'a Uri) -> Option<&'a str> {
    let bearer = headers
        .get(header::AUTHORIZATION)
        .and_then(|value| value.to_str().ok())
        .and_then(|value| {
            let (scheme, token) = value.trim().split_once(' ')?;
            scheme.eq_ignore_ascii_case("bearer").then(|| token.trim())
        });
    bearer.or_else(|| {
        uri.query()?
            .split('&')
            .find_map(|pair| pair.strip_prefix("token="))
    })
}

/// Whether two byte strings are equal, in time that depends only on their lengths.
fn same(a: &[u8], b: &[u8]) -> bool {
    if a.len() != b.len() {
        return false;
    }
    a.iter().zip(b).fold(0u8, |acc, (x, y)| acc | (x ^ y)) == 0
}

/// What one connection may do.
#[derive(Clone, PartialEq, Eq, Debug)]
pub enum Grant {
    /// Everything: the node has no credentials.
    Anyone,
    /// What this credential's role lets it do.
    Credential(Credential),
}

impl Grant {
    /// Whether the connection may call `service`: `Ok`, or why not.
    ///
    /// # Errors
    /// The refusal's message, naming the credential and what its role may do.
    pub fn may_call(&self, service: &str) -> Result<(), String> {
        let Self::Credential(credential) = self else {
            return Ok(());
        };
        let changes_operator = matches!(
            service,
            "/api/planning/cooperation/set_commands" | "/api/planning/cooperation/set_policies"
        );
        match credential.role {
            Role::Module if changes_operator => Err(format!(
                "{service:?} is the operator's: credential {:?} is a planning module's",
                credential.name
            )),
            Role::Operator if service == crate::sync::NAME => Err(format!(
                "{service:?} is the planning modules': credential {:?} is an operator's",
                credential.name
            )),
            _ => Ok(()),
        }
    }

    /// Whether the connection may report for the RTC interface `interface`: `Ok`, or why not.
    ///
    /// # Errors
    /// The refusal's message, naming the interfaces the credential may report for.
    pub fn may_report(&self, interface: &str) -> Result<(), String> {
        match self {
            Self::Anyone => Ok(()),
            Self::Credential(credential) if credential.interfaces.contains(interface) => Ok(()),
            Self::Credential(credential) => Err(format!(
                "credential {:?} may report for {}, not for {interface:?}",
                credential.name,
                credential
                    .interfaces
                    .iter()
                    .map(String::as_str)
                    .collect::<Vec<_>>()
                    .join(", ")
            )),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const INTERFACES: &[&str] = &["intersection", "lane_change_left"];
    const TOKEN: &str = "abcdefghijklmnopqrstuvwxyz012345";

    #[test]
    fn a_file_reads_and_each_mistake_is_named_with_its_line() {
        let good =
            format!("# who\noperator panel {TOKEN}\nmodule lanes {TOKEN}X lane_change_left\n");
        let credentials = Credentials::parse(&good, INTERFACES, 4).expect("reads");
        assert_eq!(credentials.list().len(), 2);
        let bad = [
            ("pilot p {TOKEN}", 1, "is not a role"),
            ("operator p", 1, "a role, a name and a token"),
            ("operator p short", 1, "at least 24"),
            ("operator p {TOKEN}\noperator p {TOKEN}Y", 2, "used twice"),
            ("operator p {TOKEN}\noperator q {TOKEN}", 2, "used twice"),
            ("module m {TOKEN}", 1, "names no RTC interface"),
            ("module m {TOKEN} nowhere", 1, "not an RTC interface"),
            ("operator p {TOKEN} intersection", 1, "only a module"),
            ("operator p {TOKEN}/", 1, "each a letter"),
            (
                "operator p aaaaaaaaaaaaaaaaaaaaaaaaaaaa",
                1,
                "1 different characters",
            ),
            (
                "operator p abcdefgabcdefgabcdefgabcdefg",
                1,
                "7 different characters",
            ),
            (
                "operator p 9hX2c4mQwZr7Lk0TtB5yNvE1aPu8sDfG",
                1,
                "an example",
            ),
            (
                "module m Qm4v8ZpLx1Ck7RtY2wHs9NbE3uJd6FgA intersection",
                1,
                "an example",
            ),
            ("# nothing", 1, "no credential"),
        ];
        for (text, line, reason) in bad {
            let text = text.replace("{TOKEN}", TOKEN);
            let error = Credentials::parse(&text, INTERFACES, 4).expect_err(&text);
            assert_eq!(error.line, line, "{text}: {error}");
            assert!(error.reason.contains(reason), "{text}: {error}");
        }
    }

    #[test]
    fn a_token_is_read_from_the_header_or_the_url_and_never_printed() {
        let credentials =
            Credentials::parse(&format!("operator panel {TOKEN}"), INTERFACES, 4).expect("reads");
        let mut headers = HeaderMap::new();
        let uri: Uri = "/".parse().expect("a URI");
        assert_eq!(
            credentials.identify(&headers, &uri),
            Err(Unidentified::NonePresented)
        );
        let with_query: Uri = format!("/?x=1&token={TOKEN}").parse().expect("a URI");
        assert_eq!(credentials.identify(&headers, &with_query), Ok(0));
        headers.insert(
            header::AUTHORIZATION,
            format!("Bearer {TOKEN}").parse().expect("a header"),
        );
        assert_eq!(credentials.identify(&headers, &uri), Ok(0));
        headers.insert(
            header::AUTHORIZATION,
            format!("Bearer {TOKEN}x").parse().expect("a header"),
        );
        assert_eq!(
            credentials.identify(&headers, &with_query),
            Err(Unidentified::Unknown)
        );
        assert!(!format!("{credentials:?}").contains(TOKEN));
    }
}
