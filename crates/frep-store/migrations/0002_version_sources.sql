-- frep-store schema 2: a version's source and parameters move to their own
-- table, and the source's size is stored.
--
-- Why: a history page needs only the small columns, but schema 1 kept them
-- in one row with the source (up to a MiB), so every listed version read
-- its source's pages: 8 ms for a page of 200 versions of a 64 KB model.
-- Now `versions` rows are small and a history page touches few pages.
--
-- `versions` is rebuilt (create, copy, drop, rename); migrate.rs runs this
-- with foreign keys off and checks them before committing, as SQLite's
-- ALTER TABLE documentation prescribes.

CREATE TABLE version_sources (
    model_id TEXT NOT NULL,
    number   INTEGER NOT NULL,
    params   BLOB NOT NULL,   -- f64 little-endian, 8 bytes each
    source   TEXT NOT NULL,
    PRIMARY KEY (model_id, number),
    FOREIGN KEY (model_id, number) REFERENCES versions(model_id, number)
) STRICT;

INSERT INTO version_sources (model_id, number, params, source)
SELECT model_id, number, params, source FROM versions;

CREATE TABLE versions_new (
    model_id      TEXT NOT NULL REFERENCES models(id),
    number        INTEGER NOT NULL CHECK (number >= 1),
    author        TEXT NOT NULL,
    created       INTEGER NOT NULL,
    restored_from INTEGER,
    source_bytes  INTEGER NOT NULL,
    message       TEXT NOT NULL,
    PRIMARY KEY (model_id, number)
) STRICT;

INSERT INTO versions_new (model_id, number, author, created, restored_from, source_bytes,
                          message)
SELECT model_id, number, author, created, restored_from, length(CAST(source AS BLOB)), message
FROM versions;

DROP TABLE versions;
ALTER TABLE versions_new RENAME TO versions;
