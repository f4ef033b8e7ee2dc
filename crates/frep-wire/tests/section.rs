//! The section plane is additive on the wire: messages and specs without it
//! read as before and are written as before (so artefact keys, hashed over
//! the spec's JSON, do not change); with it, it round-trips.

use frep_wire::{ArtefactSpec, CameraView, ClientMessage, ImageEncoding, SectionPlane};

#[test]
fn image_spec_without_a_section_is_unchanged() {
    let json = r#"{"kind":"image","camera":{"yaw":30.0,"pitch":20.0,"fov":30.0,"zoom":1.0,"pan":[0.0,0.0,0.0]},"width":64,"height":48,"format":"png","quality":90}"#;
    let spec: ArtefactSpec = serde_json::from_str(json).unwrap();
    assert!(matches!(spec, ArtefactSpec::Image { section: None, .. }));
    assert_eq!(serde_json::to_string(&spec).unwrap(), json);
}

#[test]
fn section_round_trips_in_specs_and_camera_messages() {
    let section = Some(SectionPlane {
        normal: [0.0, -1.0, 0.0],
        offset: 0.25,
    });
    let specs = [
        ArtefactSpec::Image {
            camera: CameraView::default(),
            width: 8,
            height: 8,
            format: ImageEncoding::Jpeg,
            quality: 80,
            section,
        },
        ArtefactSpec::ViewSet {
            views: 12,
            elevations: vec![20.0],
            width: 8,
            height: 8,
            format: ImageEncoding::Webp,
            quality: 80,
            fov: None,
            section,
        },
        ArtefactSpec::ViewSetIndex {
            views: 12,
            elevations: vec![20.0],
            width: 8,
            height: 8,
            format: ImageEncoding::Webp,
            quality: 80,
            fov: Some(30.0),
            section,
        },
    ];
    for spec in specs {
        let json = serde_json::to_string(&spec).unwrap();
        assert!(json.contains(r#""section":{"normal":[0.0,-1.0,0.0],"offset":0.25}"#));
        assert_eq!(serde_json::from_str::<ArtefactSpec>(&json).unwrap(), spec);
    }
    let cam = ClientMessage::Camera {
        camera: CameraView::default(),
        moving: true,
        width: 10,
        height: 10,
        section,
    };
    let json = serde_json::to_string(&cam).unwrap();
    assert_eq!(serde_json::from_str::<ClientMessage>(&json).unwrap(), cam);
    let old = r#"{"type":"camera","camera":{"yaw":0.0,"pitch":0.0,"fov":null,"zoom":1.0,"pan":[0.0,0.0,0.0]},"moving":false,"width":4,"height":4}"#;
    assert!(matches!(
        serde_json::from_str::<ClientMessage>(old).unwrap(),
        ClientMessage::Camera { section: None, .. }
    ));
}
