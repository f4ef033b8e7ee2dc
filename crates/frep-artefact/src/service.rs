//! The artefact service the server calls:
//! - register a request, getting its key and URL at once;
//! - get the body, from the disk cache, or by joining or starting the single
//!   job computing it;
//! - follow progress.
//!
//! `request` registers the recipe (compiled model, parameter values, spec)
//! under its key, so a later `GET` of the URL can compute it. Recipes are
//! bounded ([`ArtefactConfig::max_recipes`]), the least recently registered
//! forgotten first. A request with a [`SupersedeGroup`] cancels the group's
//! previous job when it is for another key and still running.
//!
//! `get` is cancel-safe. Dropping its future (the HTTP client went away)
//! leaves the flight; the last to leave cancels the job.

use std::collections::{HashMap, VecDeque};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::{Duration, Instant};

use bytes::Bytes;
use frep_render::ImagePool;
use frep_wire::{ArtefactRef, ArtefactSpec, VolumeLayout};
use tokio::sync::{watch, Semaphore};

use crate::cache::{DiskCache, Meta};
use crate::compiled::Compiled;
use crate::compute::{self, check_limits};
use crate::config::{ArtefactConfig, ArtefactLimits};
use crate::error::ArtefactError;
use crate::jobs::{Done, Flight, Outcome};
use crate::key;

/// Who a job belongs to, for superseding: e.g. `"{session}/{model}/{kind}"`.
/// A newer request of the same group cancels the older one's job.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct SupersedeGroup(pub String);

/// A body to serve.
#[derive(Clone, Debug)]
pub struct ArtefactBody {
    /// The key.
    pub key: String,
    /// The bytes (cheap to clone; an axum body as is).
    pub bytes: Bytes,
    /// Media type.
    pub media_type: String,
    /// Server time it took to compute, ms (when first computed).
    pub server_ms: f64,
    /// Whether it came from the disk cache.
    pub cached: bool,
    /// For slices: the byte mapping (the `x-frep-volume` header).
    pub volume: Option<VolumeLayout>,
}

/// What `request` remembers of an artefact.
#[derive(Clone, Debug)]
struct Recipe {
    compiled: Arc<Compiled>,
    params: Vec<f64>,
    spec: ArtefactSpec,
}

#[derive(Debug, Default)]
struct Recipes {
    map: HashMap<String, Recipe>,
    order: VecDeque<String>,
}

#[derive(Debug)]
struct Inner {
    config: ArtefactConfig,
    cache: DiskCache,
    recipes: Mutex<Recipes>,
    flights: Mutex<HashMap<String, Arc<Flight>>>,
    groups: Mutex<HashMap<SupersedeGroup, String>>,
    workers: Arc<Semaphore>,
    /// Spare image buffers, shared by the workers.
    pool: ImagePool,
    computations: AtomicU64,
    cancellations: AtomicU64,
}

/// The artefact service (cheap to clone; clones share everything).
#[derive(Clone, Debug)]
pub struct Artefacts {
    inner: Arc<Inner>,
}

/// Rebinds a poisoned lock: every critical section here is a few map
/// operations that leave the maps consistent even if interrupted by a panic.
fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|p| p.into_inner())
}

impl Artefacts {
    /// Opens the disk cache and starts the service (no threads until the
    /// first job).
    pub fn new(config: ArtefactConfig) -> Result<Artefacts, ArtefactError> {
        let cache = DiskCache::open(&config.cache_dir, config.cache_max_bytes)?;
        Ok(Artefacts {
            inner: Arc::new(Inner {
                workers: Arc::new(Semaphore::new(config.workers.max(1))),
                pool: ImagePool::new(config.image_pool_bytes),
                config,
                cache,
                recipes: Mutex::new(Recipes::default()),
                flights: Mutex::new(HashMap::new()),
                groups: Mutex::new(HashMap::new()),
                computations: AtomicU64::new(0),
                cancellations: AtomicU64::new(0),
            }),
        })
    }

    /// The request limits.
    pub fn limits(&self) -> &ArtefactLimits {
        &self.inner.config.limits
    }

    /// The spare image buffers of the workers, for other renders of the
    /// same process (e.g. a session's frames).
    pub fn image_pool(&self) -> &ImagePool {
        &self.inner.pool
    }

    /// The key of an artefact, without registering it (parameter values
    /// with the defaults filled in).
    pub fn key_of(compiled: &Compiled, params: &[f64], spec: &ArtefactSpec) -> String {
        key::key(
            compiled.graph_hash(),
            &compiled.bounds(),
            &compiled.param_values(params),
            spec,
        )
    }

    /// Registers an artefact and answers where it is, at once: `ready` (with
    /// its size and compute time) when cached. Checks the limits and the
    /// parameters; starts no work. With a group, cancels that group's
    /// previous job when it is for another key.
    pub fn request(
        &self,
        compiled: Arc<Compiled>,
        params: &[f64],
        spec: ArtefactSpec,
        group: Option<SupersedeGroup>,
    ) -> Result<ArtefactRef, ArtefactError> {
        check_limits(&spec, self.limits())?;
        let max_params = self.limits().max_params;
        compute::limit("parameters", max_params as u64, params.len() as u64)?;
        if let Some(p) = params.iter().find(|p| !p.is_finite()) {
            return Err(ArtefactError::BadRequest(format!(
                "parameter value {p} is not finite"
            )));
        }
        let params = compiled.param_values(params);
        let key = key::key(compiled.graph_hash(), &compiled.bounds(), &params, &spec);
        let r = ArtefactRef {
            url: key::url(&key, &spec),
            media_type: key::media_type(&spec).to_string(),
            ready: false,
            bytes: None,
            server_ms: None,
            key: key.clone(),
        };
        self.remember(
            &key,
            Recipe {
                compiled,
                params,
                spec,
            },
        );
        if let Some(g) = group {
            self.supersede(g, &key);
        }
        // A computed artefact is ready while its disk write is still going.
        // The flight is asked first: it leaves the map only once written.
        let flown = lock(&self.inner.flights)
            .get(&key)
            .and_then(|f| f.done_meta());
        let meta = flown.or_else(|| self.inner.cache.meta(&key));
        Ok(match meta {
            Some(m) => ArtefactRef {
                ready: true,
                bytes: Some(m.len),
                server_ms: Some(m.server_ms),
                ..r
            },
            None => r,
        })
    }

    fn remember(&self, key: &str, recipe: Recipe) {
        let mut r = lock(&self.inner.recipes);
        if r.map.insert(key.to_string(), recipe).is_none() {
            r.order.push_back(key.to_string());
        }
        while r.map.len() > self.inner.config.max_recipes.max(1) {
            match r.order.pop_front() {
                Some(old) => {
                    r.map.remove(&old);
                }
                None => break,
            }
        }
    }

    fn supersede(&self, group: SupersedeGroup, key: &str) {
        let old = lock(&self.inner.groups).insert(group, key.to_string());
        let Some(old) = old.filter(|o| o != key) else {
            return;
        };
        let mut flights = lock(&self.inner.flights);
        if let Some(f) = flights.get(&old) {
            if !f.is_finished() {
                f.cancel();
                flights.remove(&old);
            }
        }
    }

    /// The body of an artefact: from the disk cache, else from the job
    /// computing it (joined if running, started if not). Dropping the
    /// future leaves the job; the last waiter to leave cancels it.
    pub async fn get(&self, key: &str) -> Result<ArtefactBody, ArtefactError> {
        if !key::is_key(key) {
            return Err(ArtefactError::UnknownKey(key.to_string()));
        }
        if let Some(body) = self.cached(key).await? {
            return Ok(body);
        }
        let recipe = lock(&self.inner.recipes).map.get(key).cloned();
        let Some(recipe) = recipe else {
            return Err(ArtefactError::UnknownKey(key.to_string()));
        };
        let flight = self.join(key, recipe)?;
        let guard = Waiter {
            service: self,
            key,
            flight: &flight,
        };
        let outcome = flight.outcome().await;
        drop(guard);
        let done = outcome?;
        Ok(ArtefactBody {
            key: key.to_string(),
            bytes: done.bytes,
            media_type: done.meta.media_type,
            server_ms: done.meta.server_ms,
            cached: false,
            volume: done.meta.volume,
        })
    }

    async fn cached(&self, key: &str) -> Result<Option<ArtefactBody>, ArtefactError> {
        if !self.inner.cache.contains(key) {
            return Ok(None);
        }
        let inner = self.inner.clone();
        let k = key.to_string();
        let hit = tokio::task::spawn_blocking(move || inner.cache.get(&k))
            .await
            .map_err(|e| ArtefactError::Io(e.to_string()))??;
        Ok(hit.map(|(bytes, meta)| ArtefactBody {
            key: key.to_string(),
            bytes: Bytes::from(bytes),
            media_type: meta.media_type,
            server_ms: meta.server_ms,
            cached: true,
            volume: meta.volume,
        }))
    }

    /// Joins the key's flight, or starts one (refused when the queue is
    /// full).
    fn join(&self, key: &str, recipe: Recipe) -> Result<Arc<Flight>, ArtefactError> {
        let mut flights = lock(&self.inner.flights);
        if let Some(f) = flights.get(key) {
            f.join();
            return Ok(f.clone());
        }
        let cap = self.inner.config.workers.max(1) + self.inner.config.queue_max;
        if flights.len() >= cap {
            return Err(ArtefactError::Busy(flights.len()));
        }
        let f = Arc::new(Flight::new());
        f.join();
        flights.insert(key.to_string(), f.clone());
        drop(flights);
        tokio::spawn(drive(
            self.inner.clone(),
            key.to_string(),
            recipe,
            f.clone(),
        ));
        Ok(f)
    }

    /// Progress of the job computing `key` in `[0, 1]`: 1 when cached,
    /// `None` when neither running nor cached.
    pub fn progress(&self, key: &str) -> Option<f64> {
        if let Some(f) = lock(&self.inner.flights).get(key) {
            return Some(f.progress.fraction());
        }
        self.inner.cache.contains(key).then_some(1.0)
    }

    /// Progress of the job computing `key`, pushed every `every` (at least
    /// 10 ms) while it runs, then 1 when done; `None` when no job runs for
    /// it or no tokio runtime is current.
    pub fn subscribe(&self, key: &str, every: Duration) -> Option<watch::Receiver<f64>> {
        let flight = lock(&self.inner.flights).get(key).cloned()?;
        let rt = tokio::runtime::Handle::try_current().ok()?;
        let (tx, rx) = watch::channel(flight.progress.fraction());
        let every = every.max(Duration::from_millis(10));
        rt.spawn(async move {
            while !flight.is_finished() && !tx.is_closed() {
                tokio::time::sleep(every).await;
                let f = flight.progress.fraction();
                tx.send_if_modified(|v| {
                    let changed = *v != f;
                    *v = f;
                    changed
                });
            }
            let _ = tx.send(1.0);
        });
        Some(rx)
    }

    /// Jobs computed since the start (a counter for tests and metrics).
    pub fn computations(&self) -> u64 {
        self.inner.computations.load(Ordering::Relaxed)
    }

    /// Jobs ended by a cancel since the start (superseded, or nobody
    /// waited any more).
    pub fn cancellations(&self) -> u64 {
        self.inner.cancellations.load(Ordering::Relaxed)
    }

    /// Jobs running or waiting for a worker.
    pub fn in_flight(&self) -> usize {
        lock(&self.inner.flights).len()
    }

    /// Total size of the disk cache, bytes.
    pub fn cache_bytes(&self) -> u64 {
        self.inner.cache.total_bytes()
    }

    /// Whether `key` is in the disk cache.
    pub fn is_cached(&self, key: &str) -> bool {
        self.inner.cache.contains(key)
    }
}

/// A waiter of a flight: leaving (dropped, also when the `get` future is
/// dropped) as the last one cancels the job and forgets the flight.
struct Waiter<'a> {
    service: &'a Artefacts,
    key: &'a str,
    flight: &'a Arc<Flight>,
}

impl Drop for Waiter<'_> {
    fn drop(&mut self) {
        let mut flights = lock(&self.service.inner.flights);
        if self.flight.leave() && !self.flight.is_finished() {
            self.flight.cancel();
            if flights
                .get(self.key)
                .is_some_and(|f| Arc::ptr_eq(f, self.flight))
            {
                flights.remove(self.key);
            }
        }
    }
}

/// Runs one flight: waits for a worker (or the cancel), computes on a
/// blocking thread, publishes, stores in the cache, forgets the flight.
async fn drive(inner: Arc<Inner>, key: String, recipe: Recipe, flight: Arc<Flight>) {
    let permit = tokio::select! {
        p = inner.workers.clone().acquire_owned() => p.ok(),
        _ = flight.cancelled.notified() => None,
    };
    let outcome = match permit {
        Some(permit) if !flight.cancel.is_cancelled() => {
            let (inner2, key2, flight2) = (inner.clone(), key.clone(), flight.clone());
            let r = tokio::task::spawn_blocking(move || {
                let _permit = permit;
                run(&inner2, &key2, &recipe, &flight2)
            })
            .await;
            r.unwrap_or_else(|e| Err(ArtefactError::Render(format!("job failed: {e}"))))
        }
        _ => Err(ArtefactError::Cancelled),
    };
    if matches!(outcome, Err(ArtefactError::Cancelled)) {
        inner.cancellations.fetch_add(1, Ordering::Relaxed);
    }
    flight.finish(outcome);
    let mut flights = lock(&inner.flights);
    if flights.get(&key).is_some_and(|f| Arc::ptr_eq(f, &flight)) {
        flights.remove(&key);
    }
}

/// The blocking part of a job:
/// 1. compute;
/// 2. publish at once, so waiters are served before the disk write;
/// 3. write the cache.
///
/// The flight stays in the map until the write is done. So a request
/// meanwhile joins it instead of missing both.
fn run(inner: &Inner, key: &str, recipe: &Recipe, flight: &Flight) -> Outcome {
    inner.computations.fetch_add(1, Ordering::Relaxed);
    let start = Instant::now();
    let out = compute::compute(
        &recipe.compiled,
        &recipe.params,
        &recipe.spec,
        &inner.config.limits,
        &flight.cancel,
        &flight.progress,
        &inner.pool,
    )?;
    let meta = Meta {
        media_type: out.media_type.to_string(),
        len: out.bytes.len() as u64,
        server_ms: start.elapsed().as_secs_f64() * 1e3,
        volume: out.volume,
    };
    let done = Done {
        bytes: Bytes::from(out.bytes),
        meta,
    };
    flight.finish(Ok(done.clone()));
    if let Err(e) = inner.cache.put(key, &done.bytes, &done.meta) {
        tracing::warn!("artefact cache: cannot store {key}: {e}");
    }
    Ok(done)
}
