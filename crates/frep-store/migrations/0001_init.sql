-- frep-store schema 1: models, immutable versions, the change log, assets,
-- the access list. Applied once, in a transaction, by sqlite/migrate.rs.

CREATE TABLE models (
    id        TEXT PRIMARY KEY,
    name      TEXT NOT NULL,
    owner     TEXT NOT NULL,
    created   INTEGER NOT NULL,
    updated   INTEGER NOT NULL,
    latest    INTEGER NOT NULL,   -- number of the newest version
    last_seq  INTEGER NOT NULL,   -- seq of the newest log entry
    deleted   INTEGER             -- time of the delete, NULL while alive
) STRICT;

CREATE TABLE versions (
    model_id      TEXT NOT NULL REFERENCES models(id),
    number        INTEGER NOT NULL CHECK (number >= 1),
    source        TEXT NOT NULL,
    params        BLOB NOT NULL,  -- f64 little-endian, 8 bytes each
    author        TEXT NOT NULL,
    created       INTEGER NOT NULL,
    message       TEXT NOT NULL,
    restored_from INTEGER,
    PRIMARY KEY (model_id, number)
) STRICT, WITHOUT ROWID;

CREATE TABLE assets (
    hash       TEXT PRIMARY KEY,  -- BLAKE3 hex of bytes
    size       INTEGER NOT NULL,
    media_type TEXT NOT NULL,
    bytes      BLOB NOT NULL,
    created    INTEGER NOT NULL
) STRICT;

CREATE TABLE version_assets (
    model_id TEXT NOT NULL,
    number   INTEGER NOT NULL,
    name     TEXT NOT NULL,
    hash     TEXT NOT NULL REFERENCES assets(hash),
    PRIMARY KEY (model_id, number, name),
    FOREIGN KEY (model_id, number) REFERENCES versions(model_id, number)
) STRICT, WITHOUT ROWID;

CREATE TABLE changes (
    global_seq INTEGER PRIMARY KEY AUTOINCREMENT,
    model_id   TEXT NOT NULL REFERENCES models(id),
    seq        INTEGER NOT NULL CHECK (seq >= 1),
    kind       TEXT NOT NULL
               CHECK (kind IN ('created', 'saved', 'restored', 'renamed', 'deleted')),
    version    INTEGER,
    name       TEXT,
    author     TEXT NOT NULL,
    time       INTEGER NOT NULL,
    UNIQUE (model_id, seq)
) STRICT;

CREATE TABLE editors (
    model_id   TEXT NOT NULL REFERENCES models(id),
    user       TEXT NOT NULL,
    granted_by TEXT NOT NULL,
    granted    INTEGER NOT NULL,
    PRIMARY KEY (model_id, user)
) STRICT, WITHOUT ROWID;

CREATE INDEX models_alive ON models(created, id) WHERE deleted IS NULL;
CREATE INDEX version_assets_hash ON version_assets(hash);
