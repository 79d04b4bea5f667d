-- Tag entries keyed by EPC, their full revision history, and API tokens.
-- Migrations are never edited once landed: add a new numbered file instead.

create table tags (
    epc         text primary key not null,  -- upper-case hex
    entry       text not null,              -- the entry as PUT, read-only fields stripped (JSON)
    kind        text not null,              -- properties.type, for the type filter
    name        text not null,              -- properties.name, for search
    revision    integer not null,
    archived    integer not null default 0,
    updated_at  text not null,              -- RFC 3339 UTC
    updated_by  text not null
) strict;

create index tags_kind on tags (kind, epc);

create table tag_revisions (
    epc         text not null,
    revision    integer not null,
    change      text not null check (change in ('create', 'replace', 'archive', 'restore', 'retag')),
    entry       text not null,
    archived    integer not null,
    changed_at  text not null,
    changed_by  text not null,
    primary key (epc, revision)
) strict;

create table tokens (
    id          text primary key not null,  -- public handle for list and revoke
    name        text not null,
    role        text not null check (role in ('admin', 'caretaker', 'robot')),
    robot_id    text,                        -- set exactly when role = 'robot'
    secret_hash text not null unique,        -- SHA-256 of the token, hex
    created_at  text not null,
    expires_at  text,
    revoked_at  text,
    check ((role = 'robot') = (robot_id is not null))
) strict;
