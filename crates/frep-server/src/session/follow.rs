//! Following the open model. The server publishes every committed change
//! ([`crate::state::AppState::changes`]). A session tells its client when
//! someone else saved (or restored) a newer version of the model it shows.
//!
//! The session's own user is left out: the studio knows what it saved
//! itself. A session that fell behind the broadcast (lagged) asks the store
//! for the model's latest version instead. It reports it when it is newer
//! than the one open, so no new version goes unannounced.

use frep_wire::{Change, ChangeKind, ServerMessage};

use super::open::Opened;
use crate::state::AppState;

/// The message for `change`, when it is a newer version of the open model
/// by someone other than `user`.
pub fn on_change(change: &Change, opened: Option<&Opened>, user: &str) -> Option<ServerMessage> {
    let opened = opened?;
    let id = opened.model_id.as_deref()?;
    if change.model_id != id || change.author == user {
        return None;
    }
    if !matches!(change.kind, ChangeKind::Saved | ChangeKind::Restored) {
        return None;
    }
    let version = change.version?;
    if opened.version.is_some_and(|v| version <= v) {
        return None;
    }
    Some(ServerMessage::ModelChanged {
        model_id: change.model_id.clone(),
        version,
        author: change.author.clone(),
    })
}

/// After a lag: the open model's latest version when it is newer than the
/// open one.
pub async fn catch_up(
    state: AppState,
    model_id: String,
    open: Option<u32>,
) -> Option<ServerMessage> {
    let latest = crate::versions::load_version(&state, model_id.clone(), None)
        .await
        .ok()?;
    if open.is_some_and(|v| latest.number <= v) {
        return None;
    }
    Some(ServerMessage::ModelChanged {
        model_id,
        version: latest.number,
        author: latest.author,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Arc;

    fn change(kind: ChangeKind, version: Option<u32>, author: &str) -> Change {
        Change {
            seq: 1,
            model_id: "m1".into(),
            kind,
            version,
            name: None,
            author: author.into(),
            time: 0,
        }
    }

    #[test]
    fn newer_versions_by_others_are_announced() {
        let compiled = frep_artefact::compile(
            "my_model(x[3], a[1]) { my_model = 1 - x[1]^2 - x[2]^2 - x[3]^2; }",
            None,
            &Default::default(),
        )
        .unwrap();
        let opened = Opened {
            model_id: Some("m1".into()),
            version: Some(2),
            compiled,
            params: Arc::new(vec![]),
        };
        let o = Some(&opened);
        let m = on_change(&change(ChangeKind::Saved, Some(3), "bob"), o, "ann");
        assert!(matches!(
            m,
            Some(ServerMessage::ModelChanged { version: 3, .. })
        ));
        assert!(on_change(&change(ChangeKind::Saved, Some(3), "ann"), o, "ann").is_none());
        assert!(on_change(&change(ChangeKind::Saved, Some(2), "bob"), o, "ann").is_none());
        assert!(on_change(&change(ChangeKind::Renamed, None, "bob"), o, "ann").is_none());
        let mut other = change(ChangeKind::Saved, Some(9), "bob");
        other.model_id = "m2".into();
        assert!(on_change(&other, o, "ann").is_none());
        assert!(on_change(&change(ChangeKind::Saved, Some(3), "bob"), None, "ann").is_none());
    }
}
