//! The planning modules' service, `/cooperation/rtc/sync` ([`cooperation_ros::sync`]), as the
//! rosbridge node reads it: its request from JSON.

pub use cooperation_ros::sync::*;

/// The request, or a message naming the field that does not decode.
///
/// # Errors
/// The message.
pub fn read(args: &[u8]) -> Result<SyncRequest, String> {
    if args.len() > cooperation_ros::wire::MAX_REQUEST_BYTES {
        return Err(format!(
            "the request is {} bytes, more than the {} a request may have",
            args.len(),
            cooperation_ros::wire::MAX_REQUEST_BYTES
        ));
    }
    let mut reader = serde_json::Deserializer::from_slice(args);
    let request: SyncRequest = serde_path_to_error::deserialize(&mut reader).map_err(|error| {
        let path = error.path().to_string();
        let inner = error.into_inner();
        if path == "." {
            inner.to_string()
        } else {
            format!("{path}: {inner}")
        }
    })?;
    reader.end().map_err(|error| error.to_string())?;
    Ok(request)
}
