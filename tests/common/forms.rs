//! The serde forms' refusals, for the hostile-input tests of the core and of its adapters:
//! every object of a value's JSON refuses an unknown field and a field written twice.

use serde::de::DeserializeOwned;
use serde::Serialize;
use serde_json::{json, Value};

// ---------------------------------------------------------------------------------------------
// Walking a serialized value
// ---------------------------------------------------------------------------------------------

/// The paths of every JSON object inside `value`, itself included.
fn object_paths(value: &Value, path: &mut Vec<String>, out: &mut Vec<Vec<String>>) {
    match value {
        Value::Object(map) => {
            out.push(path.clone());
            for (key, inner) in map {
                path.push(key.clone());
                object_paths(inner, path, out);
                path.pop();
            }
        }
        Value::Array(items) => {
            for (index, inner) in items.iter().enumerate() {
                path.push(index.to_string());
                object_paths(inner, path, out);
                path.pop();
            }
        }
        _ => {}
    }
}

fn object_at<'a>(value: &'a mut Value, path: &[String]) -> &'a mut serde_json::Map<String, Value> {
    let mut at = value;
    for step in path {
        at = match at {
            Value::Object(map) => map.get_mut(step).expect("a key on the path"),
            Value::Array(items) => &mut items[step.parse::<usize>().expect("an index")],
            _ => unreachable!("paths lead through objects and arrays"),
        };
    }
    at.as_object_mut().expect("an object")
}

/// JSON text of `value` with the first entry of the object at `path` written twice.
fn with_first_entry_twice(value: &Value, path: &[String]) -> String {
    match value {
        Value::Object(map) => {
            let mut entries: Vec<String> = map
                .iter()
                .map(|(key, inner)| {
                    let inner = match path.split_first() {
                        Some((step, rest)) if step == key => with_first_entry_twice(inner, rest),
                        _ => inner.to_string(),
                    };
                    format!("{}:{inner}", Value::String(key.clone()))
                })
                .collect();
            if path.is_empty() {
                let first = entries[0].clone();
                entries.insert(1, first);
            }
            format!("{{{}}}", entries.join(","))
        }
        Value::Array(items) => {
            let entries: Vec<String> = items
                .iter()
                .enumerate()
                .map(|(index, inner)| match path.split_first() {
                    Some((step, rest)) if *step == index.to_string() => {
                        with_first_entry_twice(inner, rest)
                    }
                    _ => inner.to_string(),
                })
                .collect();
            format!("[{}]", entries.join(","))
        }
        other => other.to_string(),
    }
}

/// `value`'s JSON reads back as `value`; with an unknown field added to any object in it, or
/// with any object's first field written twice, it is refused.
pub fn refuses_unknown_and_repeated_fields<T>(value: &T) -> usize
where
    T: Serialize + DeserializeOwned + PartialEq + core::fmt::Debug,
{
    let json = serde_json::to_value(value).expect("serializes");
    assert_eq!(
        &serde_json::from_value::<T>(json.clone()).expect("reads back"),
        value
    );
    let mut paths = Vec::new();
    object_paths(&json, &mut Vec::new(), &mut paths);
    for path in &paths {
        let mut extended = json.clone();
        object_at(&mut extended, path).insert("unexpected".to_owned(), json!(0));
        let error = serde_json::from_value::<T>(extended).expect_err("an unknown field");
        // An enum's tag is an object of one key: a second is refused as such.
        let said = error.to_string();
        assert!(
            said.contains("unknown field") || said.contains("single key"),
            "at {path:?}: {said}"
        );
        let mut original = json.clone();
        let object = object_at(&mut original, path);
        let Some(first) = object.keys().next() else {
            continue;
        };
        // An enum's tag: an object of one key, a variant's name. Any second key is refused.
        let tag = object.len() == 1 && first.starts_with(|c: char| c.is_ascii_uppercase());
        let text = with_first_entry_twice(&json, path);
        let error = serde_json::from_str::<T>(&text).expect_err("a field given twice");
        let said = error.to_string();
        assert!(
            tag || said.contains("duplicate field"),
            "at {path:?}: {text}: {said}"
        );
    }
    paths.len()
}
