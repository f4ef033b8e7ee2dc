//! [`Store`] for [`SqliteStore`]. Each method is one transaction, and
//! delegates to the module of its table. A write runs on the writer
//! connection, a read on a read connection (see the module above).

use frep_wire::{
    Change, CreateModel, ModelDetail, ModelSummary, SourceDiff, Version, VersionSummary,
};

use super::{access, assets, check, log, models, versions, SqliteStore};
use crate::error::Result;
use crate::{Asset, AssetMeta, Committed, GlobalChange, HistoryPage, NewVersion, Store};

impl Store for SqliteStore {
    fn create_model(&self, owner: &str, model: CreateModel) -> Result<Committed<ModelDetail>> {
        self.write(|tx| models::create(tx, &self.limits, owner, model))
    }

    fn list_models(&self) -> Result<Vec<ModelSummary>> {
        self.read(models::list)
    }

    fn get_model(&self, model_id: &str) -> Result<ModelDetail> {
        self.read(|tx| models::detail(tx, model_id))
    }

    fn get_version(&self, model_id: &str, number: Option<u32>) -> Result<Version> {
        self.read(|tx| versions::get(tx, model_id, number))
    }

    fn history(&self, model_id: &str, page: HistoryPage) -> Result<Vec<VersionSummary>> {
        self.read(|tx| versions::history(tx, &self.limits, model_id, page))
    }

    fn save_version(
        &self,
        model_id: &str,
        author: &str,
        version: NewVersion,
    ) -> Result<Committed<Version>> {
        self.write(|tx| versions::save(tx, &self.limits, model_id, author, version))
    }

    fn rename(&self, model_id: &str, author: &str, name: &str) -> Result<Committed<ModelSummary>> {
        self.write(|tx| models::rename(tx, &self.limits, model_id, author, name))
    }

    fn duplicate(&self, model_id: &str, owner: &str, name: &str) -> Result<Committed<ModelDetail>> {
        self.write(|tx| models::duplicate(tx, &self.limits, model_id, owner, name))
    }

    fn restore(
        &self,
        model_id: &str,
        author: &str,
        number: u32,
        message: &str,
    ) -> Result<Committed<Version>> {
        self.write(|tx| versions::restore(tx, &self.limits, model_id, author, number, message))
    }

    fn delete(&self, model_id: &str, author: &str) -> Result<Change> {
        self.write(|tx| models::delete(tx, &self.limits, model_id, author))
    }

    fn diff(&self, model_id: &str, from: u32, to: u32) -> Result<SourceDiff> {
        self.read(|tx| versions::diff(tx, &self.limits, model_id, from, to))
    }

    fn changes(&self, model_id: &str, after: i64, limit: Option<u32>) -> Result<Vec<Change>> {
        let limit = check::page("max_changes_listed", self.limits.max_changes_listed, limit)?;
        self.read(|tx| log::changes(tx, model_id, after, limit))
    }

    fn changes_since(&self, after: i64, limit: Option<u32>) -> Result<Vec<GlobalChange>> {
        let limit = check::page("max_changes_listed", self.limits.max_changes_listed, limit)?;
        self.read(|tx| log::since(tx, after, limit))
    }

    fn put_asset(&self, bytes: &[u8], media_type: &str) -> Result<AssetMeta> {
        assets::check_put(&self.limits, bytes, media_type)?;
        // Hash before taking the writer: it is the slow part of a big put.
        let hash = assets::hash_of(bytes);
        self.write(|tx| assets::put(tx, &hash, bytes, media_type))
    }

    fn get_asset(&self, hash: &str) -> Result<Asset> {
        self.read(|tx| assets::get(tx, hash))
    }

    fn may_edit(&self, model_id: &str, user: &str) -> Result<bool> {
        self.read(|tx| access::may_edit(tx, model_id, user))
    }

    fn grant(&self, model_id: &str, by: &str, user: &str) -> Result<()> {
        self.write(|tx| access::grant(tx, &self.limits, model_id, by, user))
    }

    fn revoke(&self, model_id: &str, by: &str, user: &str) -> Result<()> {
        self.write(|tx| access::revoke(tx, model_id, by, user))
    }

    fn editors(&self, model_id: &str) -> Result<Vec<String>> {
        self.read(|tx| access::editors(tx, model_id))
    }

    fn close(&self) -> Result<()> {
        self.close_all()
    }
}
