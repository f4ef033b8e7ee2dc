//! The service: single flight, cancel when the last waiter leaves,
//! supersede, the queue bound, limits, the disk cache's bound and reopening.
//! Waits poll the service's state (no timed assertions).

use std::sync::Arc;
use std::time::Duration;

use frep_artefact::cache::{DiskCache, Meta};
use frep_artefact::{
    compile, ArtefactConfig, ArtefactError, ArtefactLimits, Artefacts, CompileLimits, Compiled,
    SupersedeGroup,
};
use frep_wire::{ArtefactSpec, CameraView, ImageEncoding};

fn example(name: &str) -> Arc<Compiled> {
    let path = format!("{}/../../examples/{name}", env!("CARGO_MANIFEST_DIR"));
    let src = std::fs::read_to_string(path).expect("example model");
    compile(&src, None, &CompileLimits::default()).expect("compiles")
}

fn service(dir: &tempfile::TempDir, workers: usize, queue: usize) -> Artefacts {
    Artefacts::new(ArtefactConfig {
        workers,
        queue_max: queue,
        ..ArtefactConfig::new(dir.path())
    })
    .unwrap()
}

fn image(size: u32, yaw: f64) -> ArtefactSpec {
    ArtefactSpec::Image {
        camera: CameraView {
            yaw,
            ..CameraView::default()
        },
        width: size,
        height: size,
        format: ImageEncoding::Png,
        quality: 80,
        section: None,
    }
}

/// A job that takes seconds in a test build: a fine mesh of the gyroid.
fn slow() -> ArtefactSpec {
    ArtefactSpec::Mesh { depth: 9 }
}

async fn until(what: &str, f: impl Fn() -> bool) {
    for _ in 0..60_000 {
        if f() {
            return;
        }
        tokio::time::sleep(Duration::from_millis(5)).await;
    }
    panic!("never: {what}");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 4)]
async fn identical_concurrent_gets_compute_once() {
    let dir = tempfile::tempdir().unwrap();
    let a = service(&dir, 2, 8);
    let r = a
        .request(example("m4_rblend10.hf"), &[], image(48, 10.0), None)
        .unwrap();
    assert!(!r.ready);
    assert_eq!(r.url, format!("/api/artefacts/{}.png", r.key));
    let gets: Vec<_> = (0..8)
        .map(|_| {
            let (a, k) = (a.clone(), r.key.clone());
            tokio::spawn(async move { a.get(&k).await })
        })
        .collect();
    let mut bodies = Vec::new();
    for g in gets {
        bodies.push(g.await.unwrap().unwrap());
    }
    assert_eq!(a.computations(), 1);
    assert!(bodies.iter().all(|b| b.bytes == bodies[0].bytes));
    assert_eq!(&bodies[0].bytes[1..4], b"PNG");
    // Now from the disk (once written: waiters are served before the
    // write), and the same request says it is ready.
    until("stored", || a.in_flight() == 0).await;
    let again = a.get(&r.key).await.unwrap();
    assert!(again.cached);
    assert_eq!(again.bytes, bodies[0].bytes);
    assert_eq!(a.computations(), 1);
    let r2 = a
        .request(example("m4_rblend10.hf"), &[], image(48, 10.0), None)
        .unwrap();
    assert_eq!(r2.key, r.key);
    assert!(r2.ready);
    assert_eq!(r2.bytes, Some(again.bytes.len() as u64));
    // Explicit default parameters are the same artefact.
    let r3 = a
        .request(example("m4_rblend10.hf"), &[0.0], image(48, 10.0), None)
        .unwrap();
    assert_eq!(r3.key, r.key);
    // A fresh service over the same folder finds it.
    drop(a);
    let b = service(&dir, 1, 1);
    assert!(b.is_cached(&r.key));
    assert!(b.get(&r.key).await.unwrap().cached);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 4)]
async fn the_last_waiter_leaving_cancels_the_job() {
    let dir = tempfile::tempdir().unwrap();
    let a = service(&dir, 1, 4);
    let r = a
        .request(example("m3_gyroid.hf"), &[], slow(), None)
        .unwrap();
    let waiters: Vec<_> = (0..2)
        .map(|_| {
            let (a, k) = (a.clone(), r.key.clone());
            tokio::spawn(async move { a.get(&k).await })
        })
        .collect();
    until("the job starts", || a.computations() == 1).await;
    assert!(a.progress(&r.key).is_some());
    waiters[0].abort();
    // One waiter is left: the job goes on.
    tokio::time::sleep(Duration::from_millis(50)).await;
    assert_eq!(a.cancellations(), 0);
    waiters[1].abort();
    // The flight is forgotten at once; the job stops soon after.
    until("the flight is forgotten", || a.in_flight() == 0).await;
    until("the job is cancelled", || a.cancellations() == 1).await;
    assert!(!a.is_cached(&r.key));
}

#[tokio::test(flavor = "multi_thread", worker_threads = 4)]
async fn a_newer_request_of_the_group_supersedes() {
    let dir = tempfile::tempdir().unwrap();
    let a = service(&dir, 2, 4);
    let g = || Some(SupersedeGroup("session 1 / model 7 / mesh".into()));
    let old = a
        .request(example("m3_gyroid.hf"), &[], slow(), g())
        .unwrap();
    let waiter = {
        let (a, k) = (a.clone(), old.key.clone());
        tokio::spawn(async move { a.get(&k).await })
    };
    until("the job starts", || a.computations() == 1).await;
    let new = a
        .request(
            example("m3_gyroid.hf"),
            &[],
            ArtefactSpec::Mesh { depth: 3 },
            g(),
        )
        .unwrap();
    assert_ne!(new.key, old.key);
    assert_eq!(waiter.await.unwrap().unwrap_err(), ArtefactError::Cancelled);
    let body = a.get(&new.key).await.unwrap();
    assert_eq!(&body.bytes[..4], b"glTF");
    assert_eq!(body.media_type, "model/gltf-binary");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 4)]
async fn a_full_queue_is_busy_and_limits_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let a = service(&dir, 1, 0);
    let c = example("m3_gyroid.hf");
    let r = a.request(c.clone(), &[], slow(), None).unwrap();
    let waiter = {
        let (a, k) = (a.clone(), r.key.clone());
        tokio::spawn(async move { a.get(&k).await })
    };
    until("the job starts", || a.computations() == 1).await;
    let other = a.request(c.clone(), &[], image(16, 0.0), None).unwrap();
    assert!(matches!(
        a.get(&other.key).await,
        Err(ArtefactError::Busy(1))
    ));
    waiter.abort();
    until("the job stops", || a.in_flight() == 0).await;
    assert!(a.get(&other.key).await.is_ok());
    let max = ArtefactLimits::default().max_mesh_depth;
    assert!(matches!(
        a.request(c.clone(), &[], ArtefactSpec::Mesh { depth: max + 1 }, None),
        Err(ArtefactError::Limit { .. })
    ));
    assert!(matches!(
        a.request(c.clone(), &[f64::NAN], image(16, 0.0), None),
        Err(ArtefactError::BadRequest(_))
    ));
    let unknown = "0".repeat(64);
    assert_eq!(
        a.get(&unknown).await.unwrap_err(),
        ArtefactError::UnknownKey(unknown.clone())
    );
    assert!(matches!(
        a.get("../etc/passwd").await,
        Err(ArtefactError::UnknownKey(_))
    ));
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_cache_stays_under_its_bound() {
    let dir = tempfile::tempdir().unwrap();
    // Each image takes about 1,000 bytes with its metadata: room for about
    // seven of the twelve, well clear of the boundary.
    let max = 7_500;
    let a = Artefacts::new(ArtefactConfig {
        cache_max_bytes: max,
        ..ArtefactConfig::new(dir.path())
    })
    .unwrap();
    let c = example("sphere.hf");
    let mut keys = Vec::new();
    for i in 0..12 {
        let r = a
            .request(c.clone(), &[], image(40, i as f64 * 30.0), None)
            .unwrap();
        let b = a.get(&r.key).await.unwrap();
        assert!(b.bytes.len() > 500);
        // Waiters are served before the disk write; the flight ends after it.
        until("stored", || a.in_flight() == 0).await;
        assert!(a.cache_bytes() <= max, "{} bytes", a.cache_bytes());
        keys.push(r.key);
    }
    // The newest is kept, the oldest went.
    assert!(a.is_cached(&keys[11]));
    assert!(!a.is_cached(&keys[0]));
    let on_disk: u64 = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().metadata().unwrap().len())
        .sum();
    assert!(on_disk <= max, "{on_disk} bytes on disk");
}

#[test]
fn the_disk_cache_evicts_the_least_recently_used() {
    let dir = tempfile::tempdir().unwrap();
    let meta = |len| Meta {
        media_type: "application/octet-stream".into(),
        len,
        server_ms: 1.0,
        volume: None,
    };
    let key = |i: u8| format!("{:064x}", i);
    let c = DiskCache::open(dir.path(), 3000).unwrap();
    for i in 0..3 {
        c.put(&key(i), &vec![i; 800], &meta(800)).unwrap();
    }
    // Touch the first: the second is now the least recently used.
    assert_eq!(c.get(&key(0)).unwrap().unwrap().0, vec![0; 800]);
    c.put(&key(3), &vec![3; 800], &meta(800)).unwrap();
    assert!(c.total_bytes() <= 3000);
    assert!(c.contains(&key(0)) && !c.contains(&key(1)) && c.contains(&key(3)));
    // Too big for the whole cache: not stored.
    c.put(&key(4), &vec![4; 4000], &meta(4000)).unwrap();
    assert!(!c.contains(&key(4)));
    // A truncated body is dropped when the folder is reopened.
    std::fs::write(dir.path().join(format!("{}.bin", key(3))), [1, 2, 3]).unwrap();
    drop(c);
    let c = DiskCache::open(dir.path(), 3000).unwrap();
    assert!(c.contains(&key(0)) && !c.contains(&key(3)));
    assert_eq!(c.get(&key(0)).unwrap().unwrap().1, meta(800));
}

#[tokio::test(flavor = "multi_thread", worker_threads = 4)]
async fn progress_is_pushed_until_done() {
    let dir = tempfile::tempdir().unwrap();
    let a = service(&dir, 1, 4);
    let r = a
        .request(
            example("m3_gyroid.hf"),
            &[],
            ArtefactSpec::Mesh { depth: 6 },
            None,
        )
        .unwrap();
    assert_eq!(a.progress(&r.key), None);
    let job = {
        let (a, k) = (a.clone(), r.key.clone());
        tokio::spawn(async move { a.get(&k).await })
    };
    until("the job starts", || a.computations() == 1).await;
    let mut rx = a
        .subscribe(&r.key, Duration::from_millis(10))
        .expect("running");
    let mut seen = vec![*rx.borrow_and_update()];
    while rx.changed().await.is_ok() {
        let v = *rx.borrow_and_update();
        seen.push(v);
        if v == 1.0 {
            break;
        }
    }
    assert_eq!(seen.last(), Some(&1.0));
    assert!(seen.iter().all(|v| (0.0..=1.0).contains(v)));
    assert!(seen.iter().any(|v| *v > 0.0 && *v < 1.0), "{seen:?}");
    let body = job.await.unwrap().unwrap();
    assert_eq!(&body.bytes[..4], b"glTF");
    until("stored", || a.in_flight() == 0).await;
    assert_eq!(a.progress(&r.key), Some(1.0));
}
