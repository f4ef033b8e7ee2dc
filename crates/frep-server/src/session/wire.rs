//! The session's messages on the socket: JSON text for [`ServerMessage`]
//! and [`ClientMessage`], and binary messages as a 4-byte little-endian
//! header length, the JSON [`BinaryHeader`], then the payload.

use axum::body::Bytes;
use axum::extract::ws::Message;
use frep_wire::{BinaryHeader, ClientMessage, ServerMessage};

/// A server message as a text frame.
pub fn text(msg: &ServerMessage) -> Message {
    // Serializing a wire enum of plain fields cannot fail; should it ever,
    // the client gets an error message rather than nothing.
    let json = serde_json::to_string(msg).unwrap_or_else(|e| {
        format!(r#"{{"type":"error","message":"cannot encode a message: {e}"}}"#)
    });
    Message::Text(json.into())
}

/// A binary frame: header length, header, payload.
pub fn binary(header: &BinaryHeader, payload: &[u8]) -> Message {
    let head = serde_json::to_vec(header).unwrap_or_default();
    let mut out = Vec::with_capacity(4 + head.len() + payload.len());
    out.extend_from_slice(&(head.len() as u32).to_le_bytes());
    out.extend_from_slice(&head);
    out.extend_from_slice(payload);
    Message::Binary(Bytes::from(out))
}

/// Reads a client's text message; the error says what is wrong with it.
pub fn parse(text: &str) -> Result<ClientMessage, String> {
    serde_json::from_str(text).map_err(|e| format!("bad message: {e}"))
}

/// An error message for the client.
pub fn error(message: impl Into<String>) -> Message {
    text(&ServerMessage::Error {
        message: message.into(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use frep_wire::CameraView;

    #[test]
    fn binary_frames_carry_their_header_length() {
        let h = BinaryHeader::Probe { id: 3, bytes: 5 };
        let Message::Binary(b) = binary(&h, b"hello") else {
            panic!("not binary");
        };
        let n = u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize;
        let back: BinaryHeader = serde_json::from_slice(&b[4..4 + n]).unwrap();
        assert_eq!(back, h);
        assert_eq!(&b[4 + n..], b"hello");
    }

    #[test]
    fn bad_messages_are_explained() {
        assert!(parse("{").unwrap_err().contains("bad message"));
        assert!(parse(r#"{"type":"nope"}"#).is_err());
        let cam = serde_json::to_string(&ClientMessage::Camera {
            camera: CameraView::default(),
            moving: true,
            width: 10,
            height: 10,
            section: None,
        })
        .unwrap();
        assert!(matches!(parse(&cam), Ok(ClientMessage::Camera { .. })));
    }
}
